/* A C11 program on the C interface of two generated models, against closed
 * forms of the simple pendulum released from rest with the bar horizontal
 * (mass m on a massless bar of length L, gravity g; IFToMM benchmark A01):
 * - period T = 4 sqrt(L/g) K(k), k = sin(theta0 / 2) (e.g. Landau & Lifshitz,
 *   Mechanics, section 11, problem 1), with the complete elliptic integral
 *   K(k) = pi / (2 AGM(1, sqrt(1 - k^2))) (Gauss's arithmetic-geometric mean);
 * - bar tension at the bottom, m g (3 - 2 cos theta0) = 3 m g, from energy
 *   conservation and the centripetal acceleration;
 * - constant total energy.
 * a01_revolute_rk4_256: the bob on a revolute joint in rk4-tree, h = 1/256 s.
 * a01_pendulum: the bob as a particle on a distance joint in staggered-pcst. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "a01_pendulum_c.h"
#include "a01_revolute_rk4_256_c.h"

static const double kPi = 3.14159265358979323846;
static const double g = 9.81, L = 1.0, m = 1.0;
static int failures = 0;

static void check(int ok, const char* what, double got, double expected) {
  printf("%s %s: got %.12g, expected %.12g\n", ok ? "ok  " : "FAIL", what, got, expected);
  if (!ok) ++failures;
}

static double agm(double a, double b) {
  while (fabs(a - b) > 1e-15 * a) {
    const double mean = 0.5 * (a + b);
    b = sqrt(a * b);
    a = mean;
  }
  return a;
}

/* Caller-owned workspace, allocated once before stepping. */
static void* allocate(size_t size, size_t align) {
  void* w = aligned_alloc(align, size); /* size is a multiple of align */
  if (!w) {
    fprintf(stderr, "cannot allocate a workspace of %zu bytes\n", size);
    exit(1);
  }
  return w;
}

/* Period from two upward zero crossings of the bob's x, and energy drift. */
static void revolute_period(void) {
  a01_revolute_rk4_256_state s;
  a01_revolute_rk4_256_work* w =
      allocate(a01_revolute_rk4_256_work_size(), a01_revolute_rk4_256_work_align());
  a01_revolute_rk4_256_init(&s, w);
  const mbrt_energy e0 = a01_revolute_rk4_256_energy(&s);
  double crossings[2];
  int n = 0;
  double drift = 0.0;
  while (n < 2 && s.t < 10.0) {
    const double t0 = s.t, x0 = s.rigid[A01_REVOLUTE_RK4_256_RIGID_BOB].r[0];
    if (a01_revolute_rk4_256_step(&s, w) != MBRT_STEP_OK) {
      check(0, "rk4-tree step status", 1, MBRT_STEP_OK);
      break;
    }
    const double x1 = s.rigid[A01_REVOLUTE_RK4_256_RIGID_BOB].r[0];
    if (x0 < 0.0 && x1 >= 0.0) crossings[n++] = t0 + (s.t - t0) * (-x0) / (x1 - x0);
    const mbrt_energy e = a01_revolute_rk4_256_energy(&s);
    drift = fmax(drift, fabs(e.kinetic + e.potential - (e0.kinetic + e0.potential)));
  }
  free(w);
  const double k = sin(0.25 * kPi);
  const double period = 4.0 * sqrt(L / g) * kPi / (2.0 * agm(1.0, sqrt(1.0 - k * k)));
  const double measured = n == 2 ? crossings[1] - crossings[0] : 0.0;
  check(fabs(measured - period) < 1e-6 * period, "rk4-tree period (s)", measured, period);
  check(drift < 1e-6 * m * g * L, "rk4-tree energy drift (J)", drift, 0.0);
}

/* Largest bar tension over the first half swing, from the reactions. */
static void distance_tension(void) {
  check(strcmp(a01_pendulum_body_names[A01_PENDULUM_BODY_BOB], "bob") == 0, "body name table", 1, 1);
  check(strcmp(a01_pendulum_constraint_names[A01_PENDULUM_CONSTRAINT_BAR], "bar") == 0, "constraint name table", 1, 1);
  a01_pendulum_state s;
  a01_pendulum_work* w = allocate(a01_pendulum_work_size(), a01_pendulum_work_align());
  a01_pendulum_init(&s, w);
  double tension = 0.0, violation = 0.0;
  const double half_period = 1.2;
  while (s.t < half_period) {
    if (a01_pendulum_step(&s, w) != MBRT_STEP_OK) {
      check(0, "staggered-pcst step status", 1, MBRT_STEP_OK);
      break;
    }
    mbrt_joint_reaction r[A01_PENDULUM_CONSTRAINT_BLOCKS];
    a01_pendulum_reactions(&s, r);
    const double* f = r[A01_PENDULUM_CONSTRAINT_BAR].force;
    tension = fmax(tension, sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
    violation = fmax(violation, a01_pendulum_constraint_violation(&s).position);
  }
  free(w);
  check(fabs(tension - 3.0 * m * g) < 1e-4 * 3.0 * m * g, "staggered-pcst bottom tension (N)", tension, 3.0 * m * g);
  check(violation < 1e-9, "staggered-pcst position violation (m)", violation, 0.0);
}

int main(void) {
  revolute_period();
  distance_tension();
  return failures == 0 ? 0 : 1;
}

/* Types every generated model's C interface (<name>_c.h) shares: plain C11,
 * the C counterparts of mbrt/model_api.hpp, mbrt/body_state.hpp and
 * mbrt/step_status.hpp (include/mbrt/c_interface.hpp copies between them). */
#ifndef MBRT_MODEL_C_H
#define MBRT_MODEL_C_H

#ifdef __cplusplus
extern "C" {
#endif

/* The generated C functions throw nothing: declared noexcept where the header
 * is read as C++. */
#ifdef __cplusplus
#define MBRT_C_NOEXCEPT noexcept
#else
#define MBRT_C_NOEXCEPT
#endif

/* Result of one step, the values of mbrt::StepStatus. A failed step leaves
 * the last good state in place. */
typedef enum mbrt_step_status {
  MBRT_STEP_OK = 0,
  MBRT_STEP_NON_FINITE = 1,   /* a NaN or Inf appeared; the state was restored */
  MBRT_STEP_NOT_POSITIVE = 2  /* the constraint matrix lost positive definiteness; the state was restored */
} mbrt_step_status;

/* A rigid body: COM position r and velocity v in world axes, Euler parameters
 * p = (e0, e1, e2, e3) body to world, angular velocity w in body axes. */
typedef struct mbrt_rigid_state {
  double r[3];
  double p[4];
  double v[3];
  double w[3];
} mbrt_rigid_state;

/* A particle: position r and velocity v, world axes. */
typedef struct mbrt_particle_state {
  double r[3];
  double v[3];
} mbrt_particle_state;

/* A rigid body's accelerations: COM a (world), angular alpha (body axes). */
typedef struct mbrt_rigid_acceleration {
  double a[3];
  double alpha[3];
} mbrt_rigid_acceleration;

typedef struct mbrt_energy {
  double kinetic;
  double potential; /* gravity (zero at the origin) plus springs */
} mbrt_energy;

/* Largest constraint residuals at position, velocity and acceleration level. */
typedef struct mbrt_constraint_violation {
  double position;
  double velocity;
  double acceleration;
} mbrt_constraint_violation;

/* Force and torque a joint or driver transmits to its body2, about body2's
 * joint point, in world axes and in the joint frame (body 1's a1, b1, c1). */
typedef struct mbrt_joint_reaction {
  double force[3], torque[3];
  double force_joint[3], torque_joint[3];
} mbrt_joint_reaction;

#ifdef __cplusplus
}
#endif

#endif /* MBRT_MODEL_C_H */

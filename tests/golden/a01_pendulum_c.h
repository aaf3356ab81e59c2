/* mbrt generated model 'a01_pendulum' from a01_pendulum.yaml: its C interface (docs/c_interface.md).
 * Plain C11 over the C++ step of a01_pendulum.hpp, implemented in a01_pendulum_c.cpp.
 * Generated code: regenerate, do not edit. */
#ifndef MBRT_MODEL_A01_PENDULUM_C_H
#define MBRT_MODEL_A01_PENDULUM_C_H

#include <stddef.h>

#include <mbrt/model_c.h>

#ifdef __cplusplus
extern "C" {
#endif

#define A01_PENDULUM_NAME "a01_pendulum"
#define A01_PENDULUM_SCHEME "staggered-pcst"
#define A01_PENDULUM_STEP 0.00050000000000000001 /* s, the time step */
#define A01_PENDULUM_BODIES 1
#define A01_PENDULUM_RIGID_BODIES 0
#define A01_PENDULUM_PARTICLES 1
#define A01_PENDULUM_CONSTRAINT_BLOCKS 1 /* joints, then drivers */
#define A01_PENDULUM_CONSTRAINT_ROWS 1

/* Indices by name: BODY_ into the body names, RIGID_ and PARTICLE_ into the
 * state's rigid and particle arrays, CONSTRAINT_ into the constraint names and
 * reactions, INPUT_ into the state's inputs, OUTPUT_ into the outputs. */
enum {
  A01_PENDULUM_BODY_BOB = 0,
  A01_PENDULUM_PARTICLE_BOB = 0,
  A01_PENDULUM_CONSTRAINT_BAR = 0,
};

/* Names in index order. */
extern const char* const a01_pendulum_body_names[A01_PENDULUM_BODIES];
extern const char* const a01_pendulum_constraint_names[A01_PENDULUM_CONSTRAINT_BLOCKS];

/* Everything that changes from step to step, member for member the C++
 * State of a01_pendulum.hpp; the caller owns it. */
typedef struct a01_pendulum_state {
  double t;
  mbrt_particle_state particle[A01_PENDULUM_PARTICLES];
  double particle_acceleration[A01_PENDULUM_PARTICLES][3];
  /* Constraint multipliers of the last step, rows as in kConstraintInfo. */
  double lambda[A01_PENDULUM_CONSTRAINT_ROWS];
} a01_pendulum_state;

/* What a step works on: caller-owned memory of a01_pendulum_work_size() bytes
 * aligned to a01_pendulum_work_align(), prepared by a01_pendulum_init(). Allocate it
 * before a real-time loop; nothing in it carries over between steps. */
typedef struct a01_pendulum_work a01_pendulum_work;
size_t a01_pendulum_work_size(void) MBRT_C_NOEXCEPT;
size_t a01_pendulum_work_align(void) MBRT_C_NOEXCEPT;

/* Sets *s to the model file's initial state and prepares *w. */
void a01_pendulum_init(a01_pendulum_state* s, a01_pendulum_work* w) MBRT_C_NOEXCEPT;
/* Advances *s by A01_PENDULUM_STEP. Allocates nothing, fixed work. On a status
 * other than MBRT_STEP_OK *s keeps its old value. */
mbrt_step_status a01_pendulum_step(a01_pendulum_state* s, a01_pendulum_work* w) MBRT_C_NOEXCEPT;
/* Nothing to do here: the step advances s->rigid itself. */
void a01_pendulum_refresh_bodies(a01_pendulum_state* s) MBRT_C_NOEXCEPT;
mbrt_energy a01_pendulum_energy(const a01_pendulum_state* s) MBRT_C_NOEXCEPT;
mbrt_constraint_violation a01_pendulum_constraint_violation(const a01_pendulum_state* s) MBRT_C_NOEXCEPT;
/* Force and torque of every joint and driver on its body2, from the
 * multipliers of the last step. */
void a01_pendulum_reactions(const a01_pendulum_state* s, mbrt_joint_reaction r[A01_PENDULUM_CONSTRAINT_BLOCKS]) MBRT_C_NOEXCEPT;

#ifdef __cplusplus
}
#endif

#endif /* MBRT_MODEL_A01_PENDULUM_C_H */

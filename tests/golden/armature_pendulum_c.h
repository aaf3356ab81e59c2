/* mbrt generated model 'armature_pendulum' from armature_pendulum.yaml: its C interface (docs/c_interface.md).
 * Plain C11 over the C++ step of armature_pendulum.hpp, implemented in armature_pendulum_c.cpp.
 * Generated code: regenerate, do not edit. */
#ifndef MBRT_MODEL_ARMATURE_PENDULUM_C_H
#define MBRT_MODEL_ARMATURE_PENDULUM_C_H

#include <stddef.h>

#include <mbrt/model_c.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ARMATURE_PENDULUM_NAME "armature_pendulum"
#define ARMATURE_PENDULUM_SCHEME "staggered-tree"
#define ARMATURE_PENDULUM_STEP 0.001 /* s, the time step */
#define ARMATURE_PENDULUM_BODIES 1
#define ARMATURE_PENDULUM_RIGID_BODIES 1
#define ARMATURE_PENDULUM_PARTICLES 0
#define ARMATURE_PENDULUM_CONSTRAINT_BLOCKS 1 /* joints, then drivers */
#define ARMATURE_PENDULUM_CONSTRAINT_ROWS 5
#define ARMATURE_PENDULUM_DOFS 1 /* joint coordinates, in body order */
#define ARMATURE_PENDULUM_OUTPUTS 1 /* values */

/* Indices by name: BODY_ into the body names, RIGID_ and PARTICLE_ into the
 * state's rigid and particle arrays, CONSTRAINT_ into the constraint names and
 * reactions, INPUT_ into the state's inputs, OUTPUT_ into the outputs. */
enum {
  ARMATURE_PENDULUM_BODY_ROD = 0,
  ARMATURE_PENDULUM_RIGID_ROD = 0,
  ARMATURE_PENDULUM_CONSTRAINT_PIN = 0,
  ARMATURE_PENDULUM_OUTPUT_PIN_ANGLE = 0, /* rad */
};

/* Names in index order. */
extern const char* const armature_pendulum_body_names[ARMATURE_PENDULUM_BODIES];
extern const char* const armature_pendulum_constraint_names[ARMATURE_PENDULUM_CONSTRAINT_BLOCKS];

/* Everything that changes from step to step, member for member the C++
 * State of armature_pendulum.hpp; the caller owns it. */
typedef struct armature_pendulum_state {
  double t;
  mbrt_rigid_state rigid[ARMATURE_PENDULUM_RIGID_BODIES];
  /* The joint coordinates (rad or m from t = 0), their rates and accelerations:
   * what step() advances; rigid holds the bodies they put where. */
  double q[ARMATURE_PENDULUM_DOFS];
  double qd[ARMATURE_PENDULUM_DOFS];
  double qdd[ARMATURE_PENDULUM_DOFS];
  /* Body accelerations and constraint multipliers at the state, which
   * step() does not need: set by initial_state() and set_multipliers(). */
  mbrt_rigid_acceleration rigid_acceleration[ARMATURE_PENDULUM_RIGID_BODIES];
  double lambda[ARMATURE_PENDULUM_CONSTRAINT_ROWS];
} armature_pendulum_state;

/* What a step works on: caller-owned memory of armature_pendulum_work_size() bytes
 * aligned to armature_pendulum_work_align(), prepared by armature_pendulum_init(). Allocate it
 * before a real-time loop; nothing in it carries over between steps. */
typedef struct armature_pendulum_work armature_pendulum_work;
size_t armature_pendulum_work_size(void) MBRT_C_NOEXCEPT;
size_t armature_pendulum_work_align(void) MBRT_C_NOEXCEPT;

/* Sets *s to the model file's initial state and prepares *w. */
void armature_pendulum_init(armature_pendulum_state* s, armature_pendulum_work* w) MBRT_C_NOEXCEPT;
/* Advances *s by ARMATURE_PENDULUM_STEP. Allocates nothing, fixed work. On a status
 * other than MBRT_STEP_OK *s keeps its old value. */
mbrt_step_status armature_pendulum_step(armature_pendulum_state* s, armature_pendulum_work* w) MBRT_C_NOEXCEPT;
/* Forms s->rigid from the joint coordinates, as the step does. */
void armature_pendulum_refresh_bodies(armature_pendulum_state* s) MBRT_C_NOEXCEPT;
/* Sets s->rigid_acceleration and s->lambda from the joint coordinates (the
 * step does not need them; the reactions do). */
void armature_pendulum_set_multipliers(armature_pendulum_state* s) MBRT_C_NOEXCEPT;
mbrt_energy armature_pendulum_energy(const armature_pendulum_state* s) MBRT_C_NOEXCEPT;
mbrt_constraint_violation armature_pendulum_constraint_violation(const armature_pendulum_state* s) MBRT_C_NOEXCEPT;
/* Force and torque of every joint and driver on its body2, from the
 * multipliers at the state. */
void armature_pendulum_reactions(const armature_pendulum_state* s, mbrt_joint_reaction r[ARMATURE_PENDULUM_CONSTRAINT_BLOCKS]) MBRT_C_NOEXCEPT;
void armature_pendulum_outputs(const armature_pendulum_state* s, double y[ARMATURE_PENDULUM_OUTPUTS]) MBRT_C_NOEXCEPT;

#ifdef __cplusplus
}
#endif

#endif /* MBRT_MODEL_ARMATURE_PENDULUM_C_H */

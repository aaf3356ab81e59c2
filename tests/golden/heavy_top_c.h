/* mbrt generated model 'heavy_top' from heavy_top.yaml: its C interface (docs/c_interface.md).
 * Plain C11 over the C++ step of heavy_top.hpp, implemented in heavy_top_c.cpp.
 * Generated code: regenerate, do not edit. */
#ifndef MBRT_MODEL_HEAVY_TOP_C_H
#define MBRT_MODEL_HEAVY_TOP_C_H

#include <stddef.h>

#include <mbrt/model_c.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HEAVY_TOP_NAME "heavy_top"
#define HEAVY_TOP_SCHEME "staggered-pcst"
#define HEAVY_TOP_STEP 0.0001 /* s, the time step */
#define HEAVY_TOP_BODIES 1
#define HEAVY_TOP_RIGID_BODIES 1
#define HEAVY_TOP_PARTICLES 0
#define HEAVY_TOP_CONSTRAINT_BLOCKS 1 /* joints, then drivers */
#define HEAVY_TOP_CONSTRAINT_ROWS 3

/* Indices by name: BODY_ into the body names, RIGID_ and PARTICLE_ into the
 * state's rigid and particle arrays, CONSTRAINT_ into the constraint names and
 * reactions, INPUT_ into the state's inputs, OUTPUT_ into the outputs. */
enum {
  HEAVY_TOP_BODY_TOP = 0,
  HEAVY_TOP_RIGID_TOP = 0,
  HEAVY_TOP_CONSTRAINT_TIP = 0,
};

/* Names in index order. */
extern const char* const heavy_top_body_names[HEAVY_TOP_BODIES];
extern const char* const heavy_top_constraint_names[HEAVY_TOP_CONSTRAINT_BLOCKS];

/* Everything that changes from step to step, member for member the C++
 * State of heavy_top.hpp; the caller owns it. */
typedef struct heavy_top_state {
  double t;
  mbrt_rigid_state rigid[HEAVY_TOP_RIGID_BODIES];
  /* Accelerations at t, reused by the next step's explicit stage. */
  mbrt_rigid_acceleration rigid_acceleration[HEAVY_TOP_RIGID_BODIES];
  /* Constraint multipliers of the last step, rows as in kConstraintInfo. */
  double lambda[HEAVY_TOP_CONSTRAINT_ROWS];
} heavy_top_state;

/* What a step works on: caller-owned memory of heavy_top_work_size() bytes
 * aligned to heavy_top_work_align(), prepared by heavy_top_init(). Allocate it
 * before a real-time loop; nothing in it carries over between steps. */
typedef struct heavy_top_work heavy_top_work;
size_t heavy_top_work_size(void) MBRT_C_NOEXCEPT;
size_t heavy_top_work_align(void) MBRT_C_NOEXCEPT;

/* Sets *s to the model file's initial state and prepares *w. */
void heavy_top_init(heavy_top_state* s, heavy_top_work* w) MBRT_C_NOEXCEPT;
/* Advances *s by HEAVY_TOP_STEP. Allocates nothing, fixed work. On a status
 * other than MBRT_STEP_OK *s keeps its old value. */
mbrt_step_status heavy_top_step(heavy_top_state* s, heavy_top_work* w) MBRT_C_NOEXCEPT;
/* Nothing to do here: the step advances s->rigid itself. */
void heavy_top_refresh_bodies(heavy_top_state* s) MBRT_C_NOEXCEPT;
mbrt_energy heavy_top_energy(const heavy_top_state* s) MBRT_C_NOEXCEPT;
mbrt_constraint_violation heavy_top_constraint_violation(const heavy_top_state* s) MBRT_C_NOEXCEPT;
/* Force and torque of every joint and driver on its body2, from the
 * multipliers of the last step. */
void heavy_top_reactions(const heavy_top_state* s, mbrt_joint_reaction r[HEAVY_TOP_CONSTRAINT_BLOCKS]) MBRT_C_NOEXCEPT;

#ifdef __cplusplus
}
#endif

#endif /* MBRT_MODEL_HEAVY_TOP_C_H */

/* mbrt generated model 'four_bar' from four_bar.yaml: its C interface (docs/c_interface.md).
 * Plain C11 over the C++ step of four_bar.hpp, implemented in four_bar_c.cpp.
 * Generated code: regenerate, do not edit. */
#ifndef MBRT_MODEL_FOUR_BAR_C_H
#define MBRT_MODEL_FOUR_BAR_C_H

#include <stddef.h>

#include <mbrt/model_c.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FOUR_BAR_NAME "four_bar"
#define FOUR_BAR_SCHEME "staggered-pcst"
#define FOUR_BAR_STEP 0.001 /* s, the time step */
#define FOUR_BAR_BODIES 3
#define FOUR_BAR_RIGID_BODIES 3
#define FOUR_BAR_PARTICLES 0
#define FOUR_BAR_CONSTRAINT_BLOCKS 4 /* joints, then drivers */
#define FOUR_BAR_CONSTRAINT_ROWS 20

/* Indices by name: BODY_ into the body names, RIGID_ and PARTICLE_ into the
 * state's rigid and particle arrays, CONSTRAINT_ into the constraint names and
 * reactions, INPUT_ into the state's inputs, OUTPUT_ into the outputs. */
enum {
  FOUR_BAR_BODY_CRANK = 0,
  FOUR_BAR_RIGID_CRANK = 0,
  FOUR_BAR_BODY_COUPLER = 1,
  FOUR_BAR_RIGID_COUPLER = 1,
  FOUR_BAR_BODY_ROCKER = 2,
  FOUR_BAR_RIGID_ROCKER = 2,
  FOUR_BAR_CONSTRAINT_PIN_O = 0,
  FOUR_BAR_CONSTRAINT_PIN_A = 1,
  FOUR_BAR_CONSTRAINT_PIN_B = 2,
  FOUR_BAR_CONSTRAINT_PIN_C = 3,
};

/* Names in index order. */
extern const char* const four_bar_body_names[FOUR_BAR_BODIES];
extern const char* const four_bar_constraint_names[FOUR_BAR_CONSTRAINT_BLOCKS];

/* Everything that changes from step to step, member for member the C++
 * State of four_bar.hpp; the caller owns it. */
typedef struct four_bar_state {
  double t;
  mbrt_rigid_state rigid[FOUR_BAR_RIGID_BODIES];
  /* Accelerations at t, reused by the next step's explicit stage. */
  mbrt_rigid_acceleration rigid_acceleration[FOUR_BAR_RIGID_BODIES];
  /* Constraint multipliers of the last step, rows as in kConstraintInfo. */
  double lambda[FOUR_BAR_CONSTRAINT_ROWS];
} four_bar_state;

/* What a step works on: caller-owned memory of four_bar_work_size() bytes
 * aligned to four_bar_work_align(), prepared by four_bar_init(). Allocate it
 * before a real-time loop; nothing in it carries over between steps. */
typedef struct four_bar_work four_bar_work;
size_t four_bar_work_size(void) MBRT_C_NOEXCEPT;
size_t four_bar_work_align(void) MBRT_C_NOEXCEPT;

/* Sets *s to the model file's initial state and prepares *w. */
void four_bar_init(four_bar_state* s, four_bar_work* w) MBRT_C_NOEXCEPT;
/* Advances *s by FOUR_BAR_STEP. Allocates nothing, fixed work. On a status
 * other than MBRT_STEP_OK *s keeps its old value. */
mbrt_step_status four_bar_step(four_bar_state* s, four_bar_work* w) MBRT_C_NOEXCEPT;
/* Nothing to do here: the step advances s->rigid itself. */
void four_bar_refresh_bodies(four_bar_state* s) MBRT_C_NOEXCEPT;
mbrt_energy four_bar_energy(const four_bar_state* s) MBRT_C_NOEXCEPT;
mbrt_constraint_violation four_bar_constraint_violation(const four_bar_state* s) MBRT_C_NOEXCEPT;
/* Force and torque of every joint and driver on its body2, from the
 * multipliers of the last step. */
void four_bar_reactions(const four_bar_state* s, mbrt_joint_reaction r[FOUR_BAR_CONSTRAINT_BLOCKS]) MBRT_C_NOEXCEPT;

#ifdef __cplusplus
}
#endif

#endif /* MBRT_MODEL_FOUR_BAR_C_H */

/* Every kind of generated C header, compiled as C11 with -pedantic -Werror
 * (test_c_interface's flags): inputs and outputs, ali3p's and generalized-alpha's
 * state members, a scene without constraints. */
#include "a01_ali3p_c.h"
#include "actuated_c.h"
#include "heavy_top_generalized_alpha_1_c.h"
#include "spring_pair_c.h"

/* The headers' sizes are constant expressions. */
_Static_assert(ACTUATED_OUTPUTS > 0 && ACTUATED_INPUTS > 0, "actuated has inputs and outputs");
_Static_assert(SPRING_PAIR_CONSTRAINT_BLOCKS == 0, "spring_pair has no constraints");

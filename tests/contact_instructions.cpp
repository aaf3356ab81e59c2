// Steps the contact test models (docs/contact.md) through sticking,
// sliding, rolling, bouncing and tumbling, free bodies and bodies in joints,
// joint friction in absolute coordinates (docs/friction.md) through
// slipping, turning and sticking, and both in one mechanism, with callgrind collecting only
// inside sampled step() calls, each dumped with its model's name. Run by
// contact_instructions.sh under valgrind, which checks that every sampled
// step of a model executes the same number of instructions.
#include <valgrind/callgrind.h>

#include "contact_balls.hpp"
#include "contact_hub_friction_pcst.hpp"
#include "contact_incline.hpp"
#include "contact_jointed.hpp"
#include "contact_tumble.hpp"
#include "friction_incline_mu_pcst.hpp"
#include "friction_pendulum_pcst.hpp"

namespace {

template <class State, class Workspace, class Step>
void sample(const char* name, State s, Step step, int steps = 4000) {
  Workspace w;
  for (int n = 0; n < steps; ++n) {
    const bool sampled = n % 40 == 0;
    if (sampled) CALLGRIND_TOGGLE_COLLECT;
    step(s, w);
    if (sampled) {
      CALLGRIND_TOGGLE_COLLECT;
      CALLGRIND_DUMP_STATS_AT(name);
    }
  }
}

}  // namespace

int main() {
  namespace balls = mbrt::models::contact_balls;
  namespace incline = mbrt::models::contact_incline;
  namespace tumble = mbrt::models::contact_tumble;
  sample<balls::State, balls::Workspace>("contact_balls", balls::initial_state(),
                                         [](balls::State& s, balls::Workspace& w) { balls::step(s, w); });
  sample<incline::State, incline::Workspace>("contact_incline", incline::initial_state(),
                                             [](incline::State& s, incline::Workspace& w) { incline::step(s, w); });
  sample<tumble::State, tumble::Workspace>("contact_tumble", tumble::initial_state(),
                                           [](tumble::State& s, tumble::Workspace& w) { tumble::step(s, w); });
  // The wheel slides and rolls, the pinned rod rebounds and rests, the
  // welded boxes stick and slide (contacts on bodies in joints).
  namespace jointed = mbrt::models::contact_jointed;
  sample<jointed::State, jointed::Workspace>(
      "contact_jointed", jointed::initial_state(), [](jointed::State& s, jointed::Workspace& w) { jointed::step(s, w); }, 2000);
  // Joint friction: the pendulum swings, turns and sticks (at 4.9 s); on the
  // inclines one block is held and one slides, under load-dependent limits.
  namespace pendulum = mbrt::models::friction_pendulum_pcst;
  sample<pendulum::State, pendulum::Workspace>(
      "friction_pendulum_pcst", pendulum::initial_state(),
      [](pendulum::State& s, pendulum::Workspace& w) { pendulum::step(s, w); }, 6000);
  namespace incline_mu = mbrt::models::friction_incline_mu_pcst;
  sample<incline_mu::State, incline_mu::Workspace>(
      "friction_incline_mu_pcst", incline_mu::initial_state(),
      [](incline_mu::State& s, incline_mu::Workspace& w) { incline_mu::step(s, w); }, 4000);
  // Wheels on frictional hubs: rolling, sliding, stopping and held.
  namespace hub = mbrt::models::contact_hub_friction_pcst;
  sample<hub::State, hub::Workspace>(
      "contact_hub_friction_pcst", hub::initial_state(), [](hub::State& s, hub::Workspace& w) { hub::step(s, w); }, 2400);
}

// The parallel step (docs/parallel.md): the same generated step run part by
// part on the model's worker threads and on the caller's thread alone gives
// the same state bit for bit, run after run; against the serial step (one
// part, S eliminated in the unconstrained order) it agrees to round-off; and
// with its workers running it allocates nothing.
//
// Models: A02's N four-bar with N = 40 (IFToMM benchmark; planar kernels) in
// staggered-pcst in two parts, beside the same scene's serial model; the
// four-corner vehicle (tools/make_vehicle.py; spatial kernels) in
// staggered-pcst in four parts (its interface factorized, and by as many
// conjugate-gradient iterations as it has rows) and in blajer in two.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "a02_n40_pcst.hpp"
#include "a02_n40_pcst_parallel.hpp"
#include "allocation_counter.hpp"
#include "vehicle_blajer_parallel.hpp"
#include "vehicle_pcst_parallel.hpp"
#include "vehicle_pcst_pcg.hpp"

namespace {

#define STEPPED_MODEL(Tag, ns)                                                                       \
  struct Tag {                                                                                       \
    using State = mbrt::models::ns::State;                                                           \
    using Workspace = mbrt::models::ns::Workspace;                                                   \
    static constexpr int kParts = mbrt::models::ns::kParts;                                          \
    static constexpr int kRigidBodies = mbrt::models::ns::kRigidBodies;                              \
    static State initial_state() { return mbrt::models::ns::initial_state(); }                       \
    static mbrt::StepStatus step(State& s, Workspace& w) { return mbrt::models::ns::step(s, w); }    \
    static mbrt::Energy energy(const State& s) { return mbrt::models::ns::energy(s); }               \
    static void start_workers() { mbrt::models::ns::start_workers(); }                               \
    static void stop_workers() { mbrt::models::ns::stop_workers(); }                                 \
  }

STEPPED_MODEL(A02Pcst, a02_n40_pcst);
STEPPED_MODEL(A02PcstParallel, a02_n40_pcst_parallel);
STEPPED_MODEL(VehiclePcstParallel, vehicle_pcst_parallel);
STEPPED_MODEL(VehiclePcstPcg, vehicle_pcst_pcg);
STEPPED_MODEL(VehicleBlajerParallel, vehicle_blajer_parallel);

// The state after `steps` steps from the initial one; every step ok.
template <class M>
typename M::State run(int steps) {
  typename M::State s = M::initial_state();
  static typename M::Workspace w;  // large models: not on the stack
  for (int i = 0; i < steps; ++i) REQUIRE(M::step(s, w) == mbrt::StepStatus::ok);
  return s;
}

template <class State>
bool same_bits(const State& a, const State& b) {
  for (size_t i = 0; i < a.rigid.size(); ++i) {
    const auto& x = a.rigid[i];
    const auto& y = b.rigid[i];
    if (!(x.r == y.r && x.p == y.p && x.v == y.v && x.w == y.w)) return false;
  }
  return a.t == b.t;
}

// Largest difference of positions and of velocities between two states.
template <class StateA, class StateB>
double largest_difference(const StateA& a, const StateB& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.rigid.size(); ++i) {
    d = std::max(d, (a.rigid[i].r - b.rigid[i].r).template lpNorm<Eigen::Infinity>());
    d = std::max(d, (a.rigid[i].v - b.rigid[i].v).template lpNorm<Eigen::Infinity>());
  }
  return d;
}

// The workers' run against the caller's thread alone, twice each way.
template <class M>
void check_same_bits(int steps) {
  const typename M::State serial = run<M>(steps);
  M::start_workers();
  const typename M::State first = run<M>(steps);
  const typename M::State second = run<M>(steps);
  M::stop_workers();
  const typename M::State after = run<M>(steps);
  CHECK(same_bits(serial, first));
  CHECK(same_bits(first, second));
  CHECK(same_bits(serial, after));
  // The runs moved: equal bits are not equal because nothing happened.
  CHECK(largest_difference(serial, M::initial_state()) > 1e-3);
}

}  // namespace

TEST_CASE("the models are split as generated: A02 in two parts, the vehicle in four and two") {
  CHECK(A02PcstParallel::kParts == 2);
  CHECK(VehiclePcstParallel::kParts == 4);
  CHECK(VehicleBlajerParallel::kParts == 2);
  CHECK(A02Pcst::kParts == 1);
}

TEST_CASE("the workers' step equals the caller's alone bit for bit, run after run") {
  SUBCASE("A02, staggered-pcst") { check_same_bits<A02PcstParallel>(300); }
  // Four parts on a CI machine's two cores wait for each other's time
  // slices: a few steps only.
  SUBCASE("the vehicle, staggered-pcst, four parts") { check_same_bits<VehiclePcstParallel>(20); }
  SUBCASE("the vehicle, blajer") { check_same_bits<VehicleBlajerParallel>(300); }
}

TEST_CASE("the parallel step agrees with the serial step to round-off") {
  // 0.5 s: before the cranks first lie flat, where the mechanism branches
  // and round-off may pick either way.
  A02PcstParallel::start_workers();
  const double difference = largest_difference(run<A02PcstParallel>(500), run<A02Pcst>(500));
  A02PcstParallel::stop_workers();
  MESSAGE("A02 after 0.5 s, parallel against serial: ", difference);
  CHECK(difference < 1e-10);
}

TEST_CASE("conjugate gradients on the interface, as many iterations as it has rows, agree with its factor") {
  // In exact arithmetic n iterations solve an n-row system; in doubles the
  // vehicle's 45-row interface comes within round-off. One step's
  // multipliers and 300 steps' motion against the factorized interface.
  const double one = largest_difference(run<VehiclePcstPcg>(1), run<VehiclePcstParallel>(1));
  const auto pcg = run<VehiclePcstPcg>(300);
  const auto direct = run<VehiclePcstParallel>(300);
  const double many = largest_difference(pcg, direct);
  double multipliers = 0.0;
  for (int i = 0; i < pcg.lambda.size(); ++i) {
    multipliers = std::max(multipliers, std::abs(pcg.lambda[i] - direct.lambda[i]) / (1.0 + std::abs(direct.lambda[i])));
  }
  MESSAGE("vehicle, conjugate gradients against the factor: after one step ", one, ", after 300 ", many,
          "; multipliers (relative) ", multipliers);
  CHECK(one < 1e-10);
  CHECK(many < 1e-9);
  CHECK(multipliers < 1e-7);
  CHECK(largest_difference(direct, VehiclePcstParallel::initial_state()) > 1e-3);
}

TEST_CASE("the parallel step with its workers running allocates nothing") {
  run<VehicleBlajerParallel>(1);  // the static workspace
  VehicleBlajerParallel::start_workers();
  typename VehicleBlajerParallel::State s = VehicleBlajerParallel::initial_state();
  static typename VehicleBlajerParallel::Workspace w;
  long allocations = 0;
  {
    AllocationCounter counter;
    for (int i = 0; i < 200; ++i) REQUIRE(VehicleBlajerParallel::step(s, w) == mbrt::StepStatus::ok);
    allocations = counter.count();
  }
  VehicleBlajerParallel::stop_workers();
  CHECK(allocations == 0);
}

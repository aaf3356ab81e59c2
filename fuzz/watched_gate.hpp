// The command gate as the fuzzers drive it, with the property both command
// fuzzers check after every cycle: the model's inputs are finite, inside
// their [min, max] and either the safe values or those of the last command
// the gate applied; every command that decoded and every malformed message
// is counted once, under its verdict.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include <mbrt/rt/command_gate.hpp>

namespace mbrt::fuzz {

inline constexpr std::int64_t kMs = 1000000;
// The defaults of `mbrt hil`: stale after 50 ms, late after 50 ms.
inline constexpr rt::GateTimes kFuzzGateTimes{50 * kMs, 50 * kMs};

template <std::size_t N>
class WatchedGate {
 public:
  using Values = typename rt::CommandGate<N>::Values;

  explicit WatchedGate(const std::array<InputInfo, N>& inputs) noexcept : inputs_(inputs), gate_(inputs, kFuzzGateTimes) {
    for (std::size_t i = 0; i < N; ++i) safe_[i] = inputs[i].safe;
  }

  void malformed() noexcept {
    gate_.reject_malformed();
    ++malformed_;
  }

  void offer(std::int64_t seq, std::int64_t age_ns, const Values& values, std::int64_t now_ns) noexcept {
    ++offered_;
    if (gate_.offer(seq, age_ns, values, now_ns) != rt::CommandVerdict::applied) return;
    last_applied_ = values;
    applied_any_ = true;
  }

  // One cycle of the loop at now_ns; true when the property holds.
  bool cycle(std::int64_t now_ns) noexcept {
    const Values& u = gate_.inputs_for_cycle(now_ns);
    bool ok = u == safe_ || (applied_any_ && u == last_applied_);
    for (std::size_t i = 0; i < N; ++i) ok = ok && std::isfinite(u[i]) && u[i] >= inputs_[i].min && u[i] <= inputs_[i].max;
    const rt::CommandCounts& c = gate_.counts();
    return ok && c.applied() + c.rejected() == offered_ + malformed_ &&
           c.by_verdict[static_cast<std::size_t>(rt::CommandVerdict::malformed)] == malformed_;
  }

 private:
  std::array<InputInfo, N> inputs_;
  rt::CommandGate<N> gate_;
  Values safe_{};
  Values last_applied_{};
  bool applied_any_ = false;
  std::int64_t offered_ = 0;
  std::int64_t malformed_ = 0;
};

}  // namespace mbrt::fuzz

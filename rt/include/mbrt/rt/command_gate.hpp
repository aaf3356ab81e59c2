// Decides which commands reach the model. A command is applied only if it
// decoded, is fresh, is newer than the last one applied, and every value is
// finite and inside its input's [min, max]; anything else is counted by
// reason and dropped. When no command has been applied for the stale
// timeout, the inputs fall back to their safe values, and the next command
// starts a new sequence (a restarted controller counts from zero again).
// Pure logic: no clock, no I/O, no allocation; the caller passes the times.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <mbrt/model_api.hpp>

namespace mbrt::rt {

enum class CommandVerdict : int {
  applied = 0,
  malformed,     // did not decode: wrong fingerprint or type, truncated, wrong length
  late,          // older than the maximum age when it arrived
  duplicate,     // same sequence number as the last applied command
  out_of_order,  // older sequence number than the last applied command
  non_finite,    // a NaN or Inf value
  out_of_range,  // a value outside its input's [min, max]
};
inline constexpr int kCommandVerdicts = 7;

inline const char* to_string(CommandVerdict v) noexcept {
  switch (v) {
    case CommandVerdict::applied: return "applied";
    case CommandVerdict::malformed: return "malformed";
    case CommandVerdict::late: return "late";
    case CommandVerdict::duplicate: return "duplicate";
    case CommandVerdict::out_of_order: return "out_of_order";
    case CommandVerdict::non_finite: return "non_finite";
    case CommandVerdict::out_of_range: return "out_of_range";
  }
  return "unknown";
}

struct CommandCounts {
  std::array<std::int64_t, kCommandVerdicts> by_verdict{};  // [applied] is the number applied
  std::int64_t missing = 0;     // sequence numbers never seen: gaps between commands that decoded
  std::int64_t stale = 0;       // times the inputs fell back to the safe values
  std::int64_t safe_cycles = 0; // cycles run on the safe values (including before the first command)

  std::int64_t applied() const noexcept { return by_verdict[0]; }
  std::int64_t rejected() const noexcept {
    std::int64_t n = 0;
    for (int v = 1; v < kCommandVerdicts; ++v) n += by_verdict[static_cast<std::size_t>(v)];
    return n;
  }
};

struct GateTimes {
  std::int64_t stale_after_ns;  // no applied command for this long: safe values
  std::int64_t max_age_ns;      // commands older than this on arrival are late
};

// An LCM command's age on arrival at now_us: it counts from the state it
// answers (state_utime, when set), else from its own time stamp utime; all
// three in microseconds, the age in nanoseconds. A command computed from old
// data is late however quickly it was sent. The time stamps come from the
// network and may be any int64: an age beyond the int64 range saturates
// instead of wrapping (an ancient command would otherwise pass as fresh).
inline std::int64_t lcm_command_age_ns(std::int64_t now_us, std::int64_t utime, std::int64_t state_utime) noexcept {
  const std::int64_t born_us = state_utime > 0 ? state_utime : utime;
  std::int64_t age_us = 0, age_ns = 0;
  if (__builtin_sub_overflow(now_us, born_us, &age_us) || __builtin_mul_overflow(age_us, 1000, &age_ns)) {
    return now_us > born_us ? std::numeric_limits<std::int64_t>::max() : std::numeric_limits<std::int64_t>::min();
  }
  return age_ns;
}

template <std::size_t N>
class CommandGate {
 public:
  using Values = std::array<double, N>;

  CommandGate(const std::array<InputInfo, N>& inputs, GateTimes times) noexcept : inputs_(inputs), times_(times) {
    for (std::size_t i = 0; i < N; ++i) safe_[i] = inputs[i].safe;
    current_ = safe_;
  }

  // A command that decoded: its sequence number, its age on arrival (now
  // minus its own time stamp) and its values, at monotonic time now_ns.
  CommandVerdict offer(std::int64_t seq, std::int64_t age_ns, const Values& values, std::int64_t now_ns) noexcept {
    const CommandVerdict v = judge(seq, age_ns, values, now_ns);
    ++counts_.by_verdict[static_cast<std::size_t>(v)];
    const bool ordered = has_sequence(now_ns);
    if (ordered && seq > last_seen_seq_) {
      // Sequence numbers come from the network and may be any int64: the
      // gap is exact in uint64 (seq > last_seen_seq_), the count saturates.
      const std::uint64_t gap = static_cast<std::uint64_t>(seq) - static_cast<std::uint64_t>(last_seen_seq_) - 1;
      const auto room = static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max() - counts_.missing);
      counts_.missing += static_cast<std::int64_t>(std::min(gap, room));
    }
    if (!ordered || seq > last_seen_seq_) last_seen_seq_ = seq;
    if (v != CommandVerdict::applied) return v;
    last_seq_ = seq;
    last_applied_ns_ = now_ns;
    ever_applied_ = true;
    current_ = values;
    fresh_ = true;
    return v;
  }

  void reject_malformed() noexcept { ++counts_.by_verdict[static_cast<std::size_t>(CommandVerdict::malformed)]; }

  // The inputs for the cycle starting at now_ns; counts one cycle.
  const Values& inputs_for_cycle(std::int64_t now_ns) noexcept {
    if (fresh_ && !has_sequence(now_ns)) {
      fresh_ = false;
      current_ = safe_;
      ++counts_.stale;
    }
    if (!fresh_) ++counts_.safe_cycles;
    return current_;
  }

  bool on_safe_values() const noexcept { return !fresh_; }
  std::int64_t last_sequence() const noexcept { return last_seq_; }
  const CommandCounts& counts() const noexcept { return counts_; }

 private:
  // The last applied command is recent enough to order the next one.
  bool has_sequence(std::int64_t now_ns) const noexcept {
    return ever_applied_ && now_ns - last_applied_ns_ <= times_.stale_after_ns;
  }

  CommandVerdict judge(std::int64_t seq, std::int64_t age_ns, const Values& values, std::int64_t now_ns) const noexcept {
    if (age_ns > times_.max_age_ns) return CommandVerdict::late;
    if (has_sequence(now_ns) && seq == last_seq_) return CommandVerdict::duplicate;
    if (has_sequence(now_ns) && seq < last_seq_) return CommandVerdict::out_of_order;
    for (std::size_t i = 0; i < N; ++i) {
      if (!std::isfinite(values[i])) return CommandVerdict::non_finite;
    }
    for (std::size_t i = 0; i < N; ++i) {
      if (values[i] < inputs_[i].min || values[i] > inputs_[i].max) return CommandVerdict::out_of_range;
    }
    return CommandVerdict::applied;
  }

  std::array<InputInfo, N> inputs_;
  GateTimes times_;
  Values safe_{};
  Values current_{};
  CommandCounts counts_;
  std::int64_t last_seq_ = -1;       // of the last applied command
  std::int64_t last_seen_seq_ = -1;  // highest of the current sequence, applied or not
  std::int64_t last_applied_ns_ = 0;
  bool ever_applied_ = false;
  bool fresh_ = false;
};

}  // namespace mbrt::rt

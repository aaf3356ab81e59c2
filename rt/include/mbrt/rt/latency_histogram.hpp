// Fixed-size histogram of durations in nanoseconds: exact below 64 ns, then
// 64 buckets per power of two (relative resolution 1/64). Recording is O(1),
// allocates nothing and never fails, so it runs on the loop path.
#pragma once

#include <array>
#include <cstdint>

namespace mbrt::rt {

class LatencyHistogram {
 public:
  void record(std::int64_t ns) noexcept;

  std::int64_t count() const noexcept { return count_; }
  std::int64_t min() const noexcept { return count_ ? min_ : 0; }
  std::int64_t max() const noexcept { return max_; }
  // Smallest bucket bound that at least a fraction q of the samples do not
  // exceed (never above the largest sample); 0 when empty.
  std::int64_t percentile(double q) const noexcept;

 private:
  static constexpr int kSubBits = 6;
  static constexpr int kSub = 1 << kSubBits;
  static constexpr int kOctaves = 63 - kSubBits;
  static int bucket_of(std::int64_t ns) noexcept;
  static std::int64_t upper_bound_of(int bucket) noexcept;

  std::array<std::int64_t, kSub * (kOctaves + 1)> counts_{};
  std::int64_t count_ = 0;
  std::int64_t min_ = 0;
  std::int64_t max_ = 0;
};

}  // namespace mbrt::rt

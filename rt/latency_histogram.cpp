#include "mbrt/rt/latency_histogram.hpp"

#include <algorithm>
#include <cmath>

namespace mbrt::rt {

// Values below kSub map to themselves; above, octave e (2^e <= v < 2^(e+1))
// keeps the kSubBits bits after the leading one.
int LatencyHistogram::bucket_of(std::int64_t ns) noexcept {
  const std::uint64_t v = ns < 0 ? 0 : static_cast<std::uint64_t>(ns);
  if (v < kSub) return static_cast<int>(v);
  const int e = 63 - __builtin_clzll(v);
  const int sub = static_cast<int>((v >> (e - kSubBits)) & (kSub - 1));
  return (e - kSubBits + 1) * kSub + sub;
}

std::int64_t LatencyHistogram::upper_bound_of(int bucket) noexcept {
  if (bucket < kSub) return bucket;
  const int e = bucket / kSub + kSubBits - 1;
  const std::uint64_t sub = static_cast<std::uint64_t>(bucket % kSub);
  return static_cast<std::int64_t>(((kSub + sub + 1) << (e - kSubBits)) - 1);
}

void LatencyHistogram::record(std::int64_t ns) noexcept {
  ns = std::max<std::int64_t>(ns, 0);
  ++counts_[static_cast<std::size_t>(bucket_of(ns))];
  min_ = count_ == 0 ? ns : std::min(min_, ns);
  max_ = std::max(max_, ns);
  ++count_;
}

std::int64_t LatencyHistogram::percentile(double q) const noexcept {
  if (count_ == 0) return 0;
  const auto rank = static_cast<std::int64_t>(std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_)));
  std::int64_t seen = 0;
  for (std::size_t b = 0; b < counts_.size(); ++b) {
    seen += counts_[b];
    if (seen >= std::max<std::int64_t>(rank, 1)) return std::min(upper_bound_of(static_cast<int>(b)), max_);
  }
  return max_;
}

}  // namespace mbrt::rt

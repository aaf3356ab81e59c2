// The latency histogram against exact order statistics of the same samples
// (sorted copies): percentiles within its stated 1/64 resolution, extremes exact.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <mbrt/rt/latency_histogram.hpp>

using mbrt::rt::LatencyHistogram;

namespace {
std::int64_t exact_percentile(std::vector<std::int64_t> v, double q) {
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::max<std::size_t>(rank, 1) - 1];
}
}  // namespace

TEST_CASE("an empty histogram reports zeros") {
  const LatencyHistogram h;
  CHECK(h.count() == 0);
  CHECK(h.percentile(0.5) == 0);
  CHECK(h.max() == 0);
}

TEST_CASE("small values are recorded exactly") {
  LatencyHistogram h;
  for (int v : {3, 1, 2, 5, 4}) h.record(v);
  CHECK(h.min() == 1);
  CHECK(h.max() == 5);
  CHECK(h.percentile(0.5) == 3);
  CHECK(h.percentile(1.0) == 5);
}

TEST_CASE("percentiles of a wide log-normal sample are within 1/64 of the exact order statistics") {
  std::mt19937_64 random(7);
  std::lognormal_distribution<double> d(std::log(20000.0), 1.5);
  std::vector<std::int64_t> samples;
  LatencyHistogram h;
  for (int i = 0; i < 200000; ++i) {
    const auto v = static_cast<std::int64_t>(d(random));
    samples.push_back(v);
    h.record(v);
  }
  CHECK(h.count() == 200000);
  CHECK(h.min() == *std::min_element(samples.begin(), samples.end()));
  CHECK(h.max() == *std::max_element(samples.begin(), samples.end()));
  for (double q : {0.01, 0.5, 0.9, 0.99, 0.999}) {
    const double exact = static_cast<double>(exact_percentile(samples, q));
    INFO("q = " << q);
    CHECK(static_cast<double>(h.percentile(q)) >= exact);
    CHECK(static_cast<double>(h.percentile(q)) <= exact * (1.0 + 1.0 / 64.0) + 1.0);
  }
}

TEST_CASE("negative durations count as zero and huge ones are kept") {
  LatencyHistogram h;
  h.record(-5);
  h.record(std::int64_t{1} << 61);
  CHECK(h.min() == 0);
  CHECK(h.max() == std::int64_t{1} << 61);
  CHECK(h.percentile(1.0) == std::int64_t{1} << 61);
}

// Percentiles of measured latencies and the counters of an authenticated-against-plain latency
// run, shared by the node-to-node benchmarks.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include <benchmark/benchmark.h>

namespace dt::bench {

// The p-quantile (0..1) of `v` by nearest rank below; 0 for no samples.
inline double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<size_t>(p * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// Medians and 99th percentiles of both runs, and plain ÷ authenticated of each (1: the MAC adds
// nothing).
inline void ReportAuthLatencyRatios(benchmark::State& state, const std::vector<double>& plain_us,
                                    const std::vector<double>& auth_us) {
  const double plain_p50 = Percentile(plain_us, 0.50), auth_p50 = Percentile(auth_us, 0.50);
  const double plain_p99 = Percentile(plain_us, 0.99), auth_p99 = Percentile(auth_us, 0.99);
  state.counters["plain_p50_us"] = plain_p50;
  state.counters["auth_p50_us"] = auth_p50;
  state.counters["plain_p99_us"] = plain_p99;
  state.counters["auth_p99_us"] = auth_p99;
  state.counters["ratio_p50"] = plain_p50 / auth_p50;
  state.counters["ratio_p99"] = plain_p99 / auth_p99;
}

}  // namespace dt::bench

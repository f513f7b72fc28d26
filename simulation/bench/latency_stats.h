// Percentiles of measured latencies and the counters of authenticated-against-plain runs
// (latency and throughput), shared by the node-to-node benchmarks.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
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

// Rates of both runs of `features` each (wall ns and this thread's CPU ns spent on each), their
// ratio by wall time and by CPU time (1: the MAC adds nothing), and CPU µs per feature.
inline void ReportAuthThroughputRatios(benchmark::State& state, double features, int64_t plain_ns,
                                       int64_t auth_ns, int64_t plain_cpu_ns, int64_t auth_cpu_ns) {
  const double plain_rate = features / (static_cast<double>(plain_ns) / 1e9);
  const double auth_rate = features / (static_cast<double>(auth_ns) / 1e9);
  state.SetItemsProcessed(static_cast<int64_t>(2 * features));
  state.counters["plain_per_s"] = plain_rate;
  state.counters["auth_per_s"] = auth_rate;
  state.counters["ratio"] = auth_rate / plain_rate;
  state.counters["cpu_ratio"] =
      static_cast<double>(plain_cpu_ns) / static_cast<double>(auth_cpu_ns);
  state.counters["plain_cpu_us"] = static_cast<double>(plain_cpu_ns) / features / 1000.0;
  state.counters["auth_cpu_us"] = static_cast<double>(auth_cpu_ns) / features / 1000.0;
}

}  // namespace dt::bench

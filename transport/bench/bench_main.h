// RunBenchmarks: the main every benchmark program shares: optionally re-executes itself in a
// private network namespace, sets up logging, runs Google Benchmark.
#pragma once

#include <cstdio>

#include <benchmark/benchmark.h>

#include "log/log.h"
#include "transport/test/private_netns.h"

namespace dt::bench {

// With `private_netns`, socket traffic only ever runs in a namespace this program makes
// (docs/pdu.md); without one, stderr says why and what `without_netns` happens to the runs.
inline int RunBenchmarks(int argc, char** argv, const char* log_name, const char* log_level,
                         bool private_netns, const char* without_netns = "") {
  if (private_netns) {
    testing::EnterPrivateNetns(argc, argv);
    if (auto reason = testing::NetnsSkipReason()) {
      std::fprintf(stderr, "no private network namespace (%s): %s\n", reason->c_str(),
                   without_netns);
    }
  }
  log::Init(log_name, log_level);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace dt::bench

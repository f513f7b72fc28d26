// Exercise file samples and helpers shared by the exercise configuration tests.
#pragma once

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "runtime/exercise_config.h"

namespace dt::test {

// A whole, valid exercise file: a server and two nodes (one with a jeep), [auth] mode "none".
inline const char* kGood = R"(
[exercise]
name = "t"
id = 7
transport = "udpm://239.255.76.67:7667?ttl=0"
run_dir = "/tmp/dt-run-t"
tick_hz = 20

[auth]
mode = "none"

[terrain]
posts_per_side = 65
spacing_m = 5.0
relief_m = 20
seed = 9

[protocol]
max_feature_period_ms = 300
silence_ms = 1500
anti_entropy_period_ms = 1500

[faults]
drop_probability = 0.3
seed = 4

[server]
name = "server"
site = 1
host = 100

[[node]]
name = "node-1"
site = 1
host = 1
scenario = "scen/a.toml"
[[node.vehicle]]
type = "jeep"
x_m = 10
z_m = 20.5
heading_deg = 90

[[node]]
name = "node-2"
site = 1
host = 2
)";

inline std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The message of the std::invalid_argument thrown for `text`, or "" if it parses.
inline std::string ErrorOf(const std::string& text) {
  try {
    ParseExerciseConfig(text, "ex.toml", "/base");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace dt::test

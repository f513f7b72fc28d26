// dt_dis: the DIS gateway (docs/dis.md "The gateway"): the exercise's vehicles and features as
// DIS 7 PDUs on UDP, and outside DIS entities (and, if allowed, craters) into the exercise.
#include <cstdio>

#include <CLI/CLI.hpp>

#include "dis/gateway_app.h"
#include "log/log.h"
#include "runtime/exercise_flags.h"

int main(int argc, char** argv) {
  CLI::App app{"The dynterrain DIS gateway: the exercise on IEEE 1278.1 UDP"};
  dt::ExerciseFlags flags;
  std::string name = "dis";
  std::string level = "info";
  flags.AddTo(app);
  app.add_option("--name", name, "the gateway's name in the exercise ([dis])")
      ->capture_default_str();
  app.add_option("--log-level", level, "debug, info, warn or error")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  try {
    dt::log::Init(name, level);
    const dt::ExerciseConfig exercise = flags.Load();
    dt::dis::GatewayApp(exercise, name).Run();
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_dis %s: %s\n", name.c_str(), e.what());
    return 2;
  }
}

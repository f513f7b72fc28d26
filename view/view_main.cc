// dt_view: the live operator view (docs/view.md): an observer replica of the exercise that
// serves a web page and pushes every change to it over a WebSocket.
#include <cstdio>

#include <CLI/CLI.hpp>

#include "log/log.h"
#include "runtime/exercise_flags.h"
#include "view/view_app.h"

int main(int argc, char** argv) {
  CLI::App app{"The dynterrain live view: a web page of the exercise as it happens"};
  dt::ExerciseFlags flags;
  std::string name = "view";
  std::string level = "info";
  dt::ViewOptions options;
  options.web_dir = DT_VIEW_WEB_DIR;
  std::string web_dir = options.web_dir.string();
  flags.AddTo(app);
  app.add_option("--name", name, "the view's name in the exercise ([view])")->capture_default_str();
  app.add_flag("--allow-commands", options.allow_commands,
               "let the page place and destroy features through the nodes' control sockets");
  app.add_option("--web-dir", web_dir, "the page's files")->capture_default_str();
  app.add_option("--log-level", level, "debug, info, warn or error")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  options.web_dir = web_dir;

  try {
    dt::log::Init(name, level);
    const dt::ExerciseConfig exercise = flags.Load();
    dt::ViewApp(exercise, name, options).Run();
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dt_view %s: %s\n", name.c_str(), e.what());
    return 2;
  }
}

// fake_child: a stand-in for dt_node / dt_server in launcher tests.
//   fake_child --name N [--config X] [--mode ready|fail|ignore-term|silent|wrapper|
//                                           escaping-wrapper] [--exit-code C] [--say LINE]...
// ready: prints a line, a partial line, then "READY N", and exits C on SIGTERM.
// fail: prints a line and exits C (3 if unset) before READY. ignore-term: READY, then answers
// each SIGTERM with the line "ignoring SIGTERM" and runs on.
// silent: never prints READY; exits C on SIGTERM.
// --say: after "starting N", each LINE on stderr (as log lines), then "said" on stdout.
// wrapper: as ready, after forking a descendant that keeps the output pipe open and waits in
// the child's process group (a wrapper such as faketime that forks); prints "descendant <pid>".
// escaping-wrapper: likewise, but the descendant moves to a process group of its own.
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {
volatile sig_atomic_t g_term = 0;
void OnTerm(int) { g_term = 1; }
void OnIgnoredTerm(int) {
  static const char kLine[] = "ignoring SIGTERM\n";
  ssize_t ignored = write(STDOUT_FILENO, kLine, sizeof(kLine) - 1);
  (void)ignored;
}
}  // namespace

int main(int argc, char** argv) {
  std::string name = "fake";
  std::string mode = "ready";
  int exit_code = -1;
  std::vector<std::string> say;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--name") == 0) name = argv[i + 1];
    if (std::strcmp(argv[i], "--mode") == 0) mode = argv[i + 1];
    if (std::strcmp(argv[i], "--exit-code") == 0) exit_code = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--say") == 0) say.push_back(argv[i + 1]);
  }
  std::printf("starting %s\n", name.c_str());
  std::fflush(stdout);
  if (!say.empty()) {
    for (const std::string& line : say) std::fprintf(stderr, "%s\n", line.c_str());
    std::fflush(stderr);
    std::printf("said\n");
    std::fflush(stdout);
  }
  if (mode == "fail") return exit_code < 0 ? 3 : exit_code;
  struct sigaction sa {};
  sa.sa_handler = mode == "ignore-term" ? OnIgnoredTerm : OnTerm;
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  if (mode == "wrapper" || mode == "escaping-wrapper") {
    std::fflush(stdout);
    const pid_t descendant = fork();
    if (descendant == 0) {
      if (mode == "escaping-wrapper") setpgid(0, 0);
      struct sigaction dfl {};
      dfl.sa_handler = SIG_DFL;
      sigaction(SIGTERM, &dfl, nullptr);
      sigaction(SIGINT, &dfl, nullptr);
      for (;;) pause();  // holds the inherited stdout and stderr until killed
    }
    std::printf("descendant %d\n", static_cast<int>(descendant));
  }
  if (mode != "silent") {
    std::fprintf(stderr, "half a ");
    std::fflush(stderr);
    std::fprintf(stderr, "line from stderr\n");
    std::printf("READY %s\n", name.c_str());
    std::fflush(stdout);
  }
  sigset_t none;
  sigemptyset(&none);
  while (g_term == 0) sigsuspend(&none);  // woken by the signal itself: no polling
  std::printf("stopping %s\n", name.c_str());
  return exit_code < 0 ? 0 : exit_code;
}

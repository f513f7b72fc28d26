#include "launcher/stop_signal_pipe.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

namespace dt {
namespace {

int g_pipe[2] = {-1, -1};

void OnStopSignal(int) {
  const char c = 's';
  ssize_t ignored = write(g_pipe[1], &c, 1);  // a full pipe already holds a wake-up
  (void)ignored;
}

}  // namespace

int InstallStopSignalPipe() {
  if (pipe2(g_pipe, O_CLOEXEC | O_NONBLOCK) != 0) return -1;
  struct sigaction sa {};
  sa.sa_handler = OnStopSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
  return g_pipe[0];
}

}  // namespace dt

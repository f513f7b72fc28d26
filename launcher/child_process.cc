#include "launcher/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

namespace dt {

std::string DescribeWaitStatus(int status) {
  if (WIFEXITED(status)) return fmt::format("exited {}", WEXITSTATUS(status));
  if (WIFSIGNALED(status)) {
    return fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)));
  }
  return fmt::format("wait status {}", status);
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv) {
  if (argv.empty()) throw std::invalid_argument("ChildProcess: empty argv");
  int out[2];
  int exec_err[2];  // CLOEXEC: closes on a successful exec, carries errno otherwise
  if (pipe2(out, O_CLOEXEC) != 0) {
    throw std::runtime_error(fmt::format("{}: pipe: {}", argv[0], std::strerror(errno)));
  }
  if (pipe2(exec_err, O_CLOEXEC) != 0) {
    close(out[0]);
    close(out[1]);
    throw std::runtime_error(fmt::format("{}: pipe: {}", argv[0], std::strerror(errno)));
  }
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  const pid_t pid = fork();
  if (pid < 0) {
    const int err = errno;
    for (int fd : {out[0], out[1], exec_err[0], exec_err[1]}) close(fd);
    throw std::runtime_error(fmt::format("{}: fork: {}", argv[0], std::strerror(err)));
  }
  if (pid == 0) {
    // Only async-signal-safe calls from here to exec.
    setpgid(0, 0);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGPIPE, SIG_DFL);
    dup2(out[1], STDOUT_FILENO);
    dup2(out[1], STDERR_FILENO);
    execvp(args[0], args.data());
    const int err = errno;
    ssize_t ignored = write(exec_err[1], &err, sizeof(err));
    (void)ignored;
    _exit(127);
  }
  pid_ = pid;
  close(out[1]);
  close(exec_err[1]);
  int err = 0;
  ssize_t n;
  do {
    n = read(exec_err[0], &err, sizeof(err));
  } while (n < 0 && errno == EINTR);
  close(exec_err[0]);
  if (n == static_cast<ssize_t>(sizeof(err))) {
    close(out[0]);
    int status = 0;
    waitpid(pid_, &status, 0);
    throw std::runtime_error(fmt::format("cannot run {}: {}", argv[0], std::strerror(err)));
  }
  out_fd_ = out[0];
  fcntl(out_fd_, F_SETFL, fcntl(out_fd_, F_GETFL, 0) | O_NONBLOCK);
}

ChildProcess::~ChildProcess() {
  if (!exited() && pid_ > 0) {
    kill(-pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
  }
  if (out_fd_ >= 0) close(out_fd_);
}

std::vector<std::string> ChildProcess::ReadLines() {
  std::vector<std::string> lines;
  if (out_fd_ < 0) return lines;
  char buf[4096];
  bool eof = false;
  for (;;) {
    const ssize_t n = read(out_fd_, buf, sizeof(buf));
    if (n > 0) {
      partial_.append(buf, static_cast<size_t>(n));
      continue;
    }
    if (n == 0) eof = true;
    if (n < 0 && errno == EINTR) continue;
    break;  // EAGAIN or error
  }
  size_t start = 0;
  for (size_t nl; (nl = partial_.find('\n', start)) != std::string::npos; start = nl + 1) {
    lines.push_back(partial_.substr(start, nl - start));
  }
  partial_.erase(0, start);
  if (eof) {
    if (!partial_.empty()) lines.push_back(std::move(partial_));
    partial_.clear();
    close(out_fd_);
    out_fd_ = -1;
  }
  return lines;
}

bool ChildProcess::Reap() {
  if (exited()) return true;
  int status = 0;
  const pid_t r = waitpid(pid_, &status, WNOHANG);
  if (r == pid_) wait_status_ = status;
  return exited();
}

void ChildProcess::Signal(int signal_number) const {
  // The child made its own group (setpgid in the fork), so its PID is the group's ID.
  if (!exited() && pid_ > 0) kill(-pid_, signal_number);
}

std::vector<std::string> ChildProcess::FinishOutput() {
  if (!exited() || out_fd_ < 0) return {};
  // The group's ID cannot be reused while a member lives, and a member is what may hold the
  // pipe: the kill reaches only the dead child's own descendants.
  kill(-pid_, SIGKILL);
  std::vector<std::string> lines = ReadLines();
  if (out_fd_ >= 0) {
    // Still open: a descendant outside the group holds the write end. What the child wrote
    // before it exited was in the pipe and has been read; stop here.
    if (!partial_.empty()) lines.push_back(std::move(partial_));
    partial_.clear();
    close(out_fd_);
    out_fd_ = -1;
  }
  return lines;
}

}  // namespace dt

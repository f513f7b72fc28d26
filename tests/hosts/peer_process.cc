#include "tests/hosts/peer_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "simulation/bench/lcm_cluster.h"

extern char** environ;

namespace dt::hostsbench {
namespace {

int64_t NowMs() { return bench::SteadyNowNs() / 1000000; }

Answer ParseAnswer(const std::string& who, const std::string& command, const std::string& rest) {
  std::istringstream in(rest);
  std::string word;
  in >> word;
  if (word != "ok") {
    throw std::runtime_error(who + ": `" + command + "` failed: " + rest);
  }
  Answer a;
  in >> a.t_ns;
  for (std::string v; in >> v;) a.values.push_back(v);
  return a;
}

}  // namespace

PeerProcess::PeerProcess(std::string name, const std::vector<std::string>& argv, int timeout_ms)
    : name_(std::move(name)) {
  int in[2], out[2];
  if (pipe2(in, O_CLOEXEC) != 0 || pipe2(out, O_CLOEXEC) != 0) {
    throw std::runtime_error(name_ + ": pipe: " + std::strerror(errno));
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int rc = posix_spawnp(&pid_, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(in[0]);
  close(out[1]);
  in_fd_ = in[1];
  out_fd_ = out[0];
  if (rc != 0) {
    close(in_fd_);
    close(out_fd_);
    throw std::runtime_error(name_ + ": cannot start " + argv[0] + ": " + std::strerror(rc));
  }
  (void)fcntl(out_fd_, F_SETFL, O_NONBLOCK);
  sent_[0] = "start";
  started_ns_ = Wait(0, timeout_ms).t_ns;
}

PeerProcess::~PeerProcess() {
  Kill();
  close(in_fd_);
  close(out_fd_);
}

void PeerProcess::Kill() {
  if (pid_ <= 0) return;
  (void)kill(pid_, SIGKILL);
  int status = 0;
  (void)waitpid(pid_, &status, 0);
  pid_ = -1;
}

int PeerProcess::Send(const std::string& command) {
  const int id = next_id_++;
  sent_[id] = command;
  const std::string line = std::to_string(id) + " " + command + "\n";
  if (pid_ <= 0 || write(in_fd_, line.data(), line.size()) != static_cast<ssize_t>(line.size())) {
    throw std::runtime_error(name_ + ": cannot send `" + command + "`: it has ended");
  }
  return id;
}

void PeerProcess::ReadAvailable() {
  char buf[4096];
  ssize_t n;
  while ((n = read(out_fd_, buf, sizeof buf)) > 0) partial_.append(buf, static_cast<size_t>(n));
  for (size_t nl; (nl = partial_.find('\n')) != std::string::npos;) {
    const std::string line = partial_.substr(0, nl);
    partial_.erase(0, nl + 1);
    const size_t space = line.find(' ');
    const std::string id = line.substr(0, space);
    // Anything else (a library's own line) is not an answer: ignored.
    if (space == std::string::npos || id.empty() || id.size() > 9 ||
        id.find_first_not_of("0123456789") != std::string::npos) {
      continue;
    }
    answers_[std::stoi(id)] = line.substr(space + 1);
  }
}

bool PeerProcess::Poll(int id, Answer& out) {
  ReadAvailable();
  auto it = answers_.find(id);
  if (it == answers_.end()) return false;
  out = ParseAnswer(name_, sent_[id], it->second);
  answers_.erase(it);
  return true;
}

Answer PeerProcess::Wait(int id, int timeout_ms) {
  const int64_t deadline = NowMs() + timeout_ms;
  Answer a;
  while (!Poll(id, a)) {
    const int64_t left = deadline - NowMs();
    if (left <= 0) {
      throw std::runtime_error(name_ + ": no answer to `" + sent_[id] + "` within " +
                               std::to_string(timeout_ms) + " ms");
    }
    pollfd fd{out_fd_, POLLIN, 0};
    if (poll(&fd, 1, static_cast<int>(std::min<int64_t>(left, 100))) > 0 &&
        (fd.revents & (POLLHUP | POLLERR)) != 0 && (fd.revents & POLLIN) == 0) {
      throw std::runtime_error(name_ + ": ended before answering `" + sent_[id] + "`");
    }
  }
  return a;
}

std::pair<size_t, Answer> WaitFirst(const std::vector<std::pair<PeerProcess*, int>>& waits,
                                    int timeout_ms) {
  const int64_t deadline = NowMs() + timeout_ms;
  while (NowMs() < deadline) {
    std::vector<pollfd> fds;
    for (size_t i = 0; i < waits.size(); ++i) {
      Answer a;
      if (waits[i].first->Poll(waits[i].second, a)) return {i, a};
      fds.push_back({waits[i].first->out_fd(), POLLIN, 0});
    }
    (void)poll(fds.data(), fds.size(), 10);
  }
  throw std::runtime_error("no answer from any of " + std::to_string(waits.size()) +
                           " peers within " + std::to_string(timeout_ms) + " ms");
}

}  // namespace dt::hostsbench

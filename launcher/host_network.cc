#include "launcher/host_network.h"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

extern char** environ;

namespace dt {
namespace {

constexpr const char* kNetnsDir = "/run/netns";

// Runs argv (no shell), returns its exit status and what it wrote to stdout and stderr.
std::pair<int, std::string> Run(const std::vector<std::string>& argv) {
  int fds[2];
  if (pipe(fds) != 0) return {-1, "pipe failed"};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 2);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) != 0;) {
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) break;
    out.append(buf, static_cast<size_t>(n));
  }
  close(fds[0]);
  if (spawned != 0) return {-1, fmt::format("cannot start {}: errno {}", argv[0], spawned)};
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

void MustRun(const std::vector<std::string>& argv) {
  auto [rc, out] = Run(argv);
  if (rc != 0) {
    throw std::runtime_error(
        fmt::format("hosts mode: `{}` failed ({}): {}", fmt::join(argv, " "), rc, out));
  }
}

}  // namespace

std::string HostsUdpmUrl(const std::string& url) {
  const size_t q = url.find('?');
  if (q == std::string::npos) return url + "?ttl=1";
  std::string out = url.substr(0, q + 1);
  std::stringstream options(url.substr(q + 1));
  bool found = false;
  bool first = true;
  for (std::string option; std::getline(options, option, '&');) {
    if (option.rfind("ttl=", 0) == 0) {
      option = "ttl=1";
      found = true;
    }
    out += (first ? "" : "&") + option;
    first = false;
  }
  if (!found) out += "&ttl=1";
  return out;
}

void ApplyHostsOverride(ExerciseConfig& exercise, const std::string& mode) {
  if (mode.empty()) return;
  const std::optional<HostsMode> m = ParseHostsMode(mode);
  if (!m) {
    throw std::invalid_argument(fmt::format("--hosts \"{}\": expected none, lan or wan", mode));
  }
  exercise.hosts.mode = *m;
}

HostNetwork::HostNetwork(const ExerciseConfig& exercise)
    : mode_(exercise.hosts.mode), prefix_(fmt::format("dt{}-", getpid())) {
  if (mode_ == HostsMode::kNone) {
    throw std::invalid_argument("HostNetwork: the exercise's hosts mode is none");
  }
  if (geteuid() != 0) {
    throw std::runtime_error(fmt::format(
        "hosts mode \"{}\" makes network namespaces, veth links and bridges and needs root "
        "(effective uid {}): run as root, or without hosts mode",
        HostsModeName(mode_), geteuid()));
  }
  std::vector<const ProcessConfig*> processes = exercise.Processes();
  if (exercise.view) processes.push_back(&exercise.view->process);
  if (exercise.dis) processes.push_back(&exercise.dis->process);
  std::set<int> sites;
  int index = 0;
  for (const ProcessConfig* p : processes) {
    const NodeAddress a = p->address;
    if (a.site < 1 || a.site > 250 || a.host < 1 || a.host > 253) {
      throw std::runtime_error(fmt::format(
          "hosts mode: {} is {}:{}, but a host's address is 10.77.<site>.<host> with site in "
          "1..250 and host in 1..253",
          p->name, a.site, a.host));
    }
    hosts_[p->name] = Host{prefix_ + p->name, fmt::format("p{}", index++), a.site, a.host};
    sites.insert(a.site);
  }
  sites_.assign(sites.begin(), sites.end());
  RemoveStale();
  try {
    Make(exercise);
  } catch (...) {
    RemoveAll();
    throw;
  }
}

HostNetwork::~HostNetwork() { RemoveAll(); }

std::string HostNetwork::SiteNamespace(int site) const {
  return mode_ == HostsMode::kLan ? prefix_ + "lan" : fmt::format("{}site{}", prefix_, site);
}

void HostNetwork::Make(const ExerciseConfig& exercise) {
  const std::string rate =
      fmt::format("{}kbit", static_cast<int64_t>(exercise.hosts.rate_mbit * 1000));
  const std::string latency = fmt::format("{}ms", exercise.hosts.queue_ms);
  auto add_ns = [&](const std::string& ns) {
    MustRun({"ip", "netns", "add", ns});
    made_.push_back(ns);
    MustRun({"ip", "-n", ns, "link", "set", "lo", "up"});
  };
  auto shape = [&](const std::string& ns, const std::string& dev) {
    // burst: at least one full packet per timer tick at this rate (tbf refuses less).
    MustRun({"tc", "-n", ns, "qdisc", "add", "dev", dev, "root", "tbf", "rate", rate, "burst",
             "64kb", "latency", latency});
  };
  std::vector<int> bridge_sites = mode_ == HostsMode::kLan ? std::vector<int>{0} : sites_;
  for (int s : bridge_sites) {
    const std::string ns = SiteNamespace(s);
    add_ns(ns);
    // Snooping off: a bridge without a querier would otherwise forget who joined a group when a
    // link goes down and comes back.
    for (const char* br : {"br0", "br1"}) {
      MustRun({"ip", "-n", ns, "link", "add", br, "type", "bridge", "mcast_snooping", "0"});
      MustRun({"ip", "-n", ns, "link", "set", br, "up"});
    }
  }
  const std::string mask = mode_ == HostsMode::kLan ? "/16" : "/24";
  for (const auto& [name, h] : hosts_) {
    const std::string site_ns = SiteNamespace(mode_ == HostsMode::kLan ? 0 : h.site);
    add_ns(h.ns);
    MustRun({"ip", "-n", site_ns, "link", "add", h.port, "type", "veth", "peer", "name", "dt0",
             "netns", h.ns});
    MustRun({"ip", "-n", site_ns, "link", "set", h.port, "master", "br0", "up"});
    MustRun({"ip", "-n", h.ns, "addr", "add", fmt::format("10.77.{}.{}{}", h.site, h.host, mask),
             "dev", "dt0"});
    MustRun({"ip", "-n", h.ns, "link", "set", "dt0", "up"});
    // Multicast (LCM's group, DDS discovery) goes out on dt0, never anywhere else.
    MustRun({"ip", "-n", h.ns, "route", "add", "224.0.0.0/4", "dev", "dt0"});
    if (mode_ == HostsMode::kWan) {
      MustRun({"ip", "-n", h.ns, "route", "add", "default", "via",
               fmt::format("10.77.{}.254", h.site)});
    }
    shape(h.ns, "dt0");
  }
  if (mode_ == HostsMode::kWan) {
    const std::string router = prefix_ + "router";
    add_ns(router);
    MustRun({"ip", "netns", "exec", router, "sysctl", "-q", "-w", "net.ipv4.ip_forward=1"});
    for (int s : sites_) {
      const std::string dev = fmt::format("s{}", s);
      MustRun({"ip", "-n", SiteNamespace(s), "link", "add", "router", "type", "veth", "peer",
               "name", dev, "netns", router});
      MustRun({"ip", "-n", SiteNamespace(s), "link", "set", "router", "master", "br0", "up"});
      MustRun({"ip", "-n", router, "addr", "add", fmt::format("10.77.{}.254/24", s), "dev", dev});
      MustRun({"ip", "-n", router, "link", "set", dev, "up"});
      shape(router, dev);
    }
  }
}

void HostNetwork::RemoveAll() noexcept {
  // Deleting a namespace removes its links and bridges with it; a host's processes are stopped
  // before this (the supervisor is destroyed first).
  for (auto it = made_.rbegin(); it != made_.rend(); ++it) {
    try {
      (void)Run({"ip", "netns", "del", *it});
    } catch (...) {
      // Nothing to do but go on with the next: the next launcher's RemoveStale retries it.
    }
  }
  made_.clear();
}

void HostNetwork::RemoveStale() {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(kNetnsDir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("dt", 0) != 0) continue;
    const size_t dash = name.find('-');
    if (dash == std::string::npos || dash == 2) continue;
    const std::string digits = name.substr(2, dash - 2);
    if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      continue;
    }
    const pid_t pid = static_cast<pid_t>(std::stol(digits));
    if (pid == getpid() || kill(pid, 0) == 0 || errno != ESRCH) continue;
    // Its launcher died without stopping them: what still runs on the host goes with it.
    auto [rc, out] = Run({"ip", "netns", "pids", name});
    std::stringstream pids(out);
    for (pid_t p; rc == 0 && pids >> p;) kill(p, SIGKILL);
    (void)Run({"ip", "netns", "del", name});
  }
}

std::vector<std::string> HostNetwork::OnHost(const std::string& process,
                                             std::vector<std::string> argv) const {
  std::vector<std::string> out = {"ip", "netns", "exec", Namespace(process)};
  out.insert(out.end(), argv.begin(), argv.end());
  return out;
}

std::string HostNetwork::Namespace(const std::string& process) const {
  auto it = hosts_.find(process);
  if (it == hosts_.end()) {
    throw std::invalid_argument(fmt::format("hosts mode: no host for process \"{}\"", process));
  }
  return it->second.ns;
}

std::string HostNetwork::Address(const std::string& process) const {
  Namespace(process);  // throws for an unknown name
  const Host& h = hosts_.at(process);
  return fmt::format("10.77.{}.{}", h.site, h.host);
}

void HostNetwork::Cut(const std::vector<std::string>& side,
                      const std::vector<std::string>& others) {
  (void)others;  // everyone not on `side` stays where they are: with `others`
  for (const std::string& n : side) Namespace(n);
  if (side.size() == 1) {
    const Host& h = hosts_.at(side[0]);
    MustRun({"ip", "-n", SiteNamespace(mode_ == HostsMode::kLan ? 0 : h.site), "link", "set",
             h.port, "down"});
    return;
  }
  if (mode_ != HostsMode::kLan) {
    throw std::runtime_error(
        fmt::format("hosts mode wan: a partition cuts one host's link; {} hosts ({}) cannot be cut "
                    "off together",
                    side.size(), fmt::join(side, ", ")));
  }
  for (const std::string& n : side) {
    MustRun({"ip", "-n", SiteNamespace(0), "link", "set", hosts_.at(n).port, "master", "br1"});
  }
  split_ = true;
}

void HostNetwork::Heal() {
  for (const auto& [name, h] : hosts_) {
    const std::string ns = SiteNamespace(mode_ == HostsMode::kLan ? 0 : h.site);
    if (split_) MustRun({"ip", "-n", ns, "link", "set", h.port, "master", "br0"});
    MustRun({"ip", "-n", ns, "link", "set", h.port, "up"});
  }
  split_ = false;
}

void HostNetwork::KillHost(const std::string& process) const {
  auto [rc, out] = Run({"ip", "netns", "pids", Namespace(process)});
  if (rc != 0) return;
  std::stringstream pids(out);
  for (pid_t pid; pids >> pid;) kill(pid, SIGKILL);
}

std::string HostsCycloneConfig(HostsMode mode, const std::vector<std::string>& peer_addresses) {
  const bool wan = mode == HostsMode::kWan;
  std::string peers;
  for (const std::string& a : peer_addresses) {
    peers += fmt::format("        <Peer address=\"{}\"/>\n", a);
  }
  // One process a host: a participant index of 0 normally; the headroom covers a restarted
  // process whose predecessor's participant has not yet timed out.
  return fmt::format(
      R"(<?xml version="1.0" encoding="UTF-8"?>
<!-- Generated by the launcher's hosts mode ({}) from the exercise file (docs/deploy.md). -->
<CycloneDDS xmlns="https://cdds.io/config">
  <Domain id="any">
    <General>
      <Interfaces>
        <NetworkInterface name="dt0"/>
      </Interfaces>
      <AllowMulticast>{}</AllowMulticast>
      <MaxMessageSize>1472B</MaxMessageSize>
    </General>
    <Discovery>
      <ParticipantIndex>auto</ParticipantIndex>
      <MaxAutoParticipantIndex>{}</MaxAutoParticipantIndex>
{}    </Discovery>
    <Tracing>
      <Verbosity>warning</Verbosity>
      <OutputFile>stderr</OutputFile>
    </Tracing>
  </Domain>
</CycloneDDS>
)",
      HostsModeName(mode), wan ? "false" : "true", wan ? 3 : 30,
      wan ? "      <Peers>\n" + peers + "      </Peers>\n" : std::string());
}

std::string HostNetwork::CarrierUrl(const std::string& url,
                                    const std::filesystem::path& dir) const {
  if (url.rfind("udpm://", 0) == 0) return HostsUdpmUrl(url);
  if (url.rfind("dds://", 0) != 0) {
    throw std::invalid_argument(
        fmt::format("hosts mode: transport \"{}\" cannot span hosts (udpm:// or dds:// can)", url));
  }
  const std::filesystem::path file = dir / "cyclonedds-hosts.xml";
  std::vector<std::string> peers;
  if (mode_ == HostsMode::kWan) {
    for (const auto& [name, h] : hosts_) peers.push_back(Address(name));
  }
  std::ofstream(file) << HostsCycloneConfig(mode_, peers);
  // Keep the domain and every option but the configuration file.
  const size_t q = url.find('?');
  std::string out = url.substr(0, q) + "?config=" + file.string();
  if (q != std::string::npos) {
    std::stringstream options(url.substr(q + 1));
    for (std::string option; std::getline(options, option, '&');) {
      if (option.rfind("config=", 0) != 0) out += "&" + option;
    }
  }
  return out;
}

}  // namespace dt

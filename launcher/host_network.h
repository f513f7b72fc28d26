// HostNetwork: the hosts mode's network namespaces, bridges, links and router, made and removed
// by the launcher itself (docs/deploy.md "Trying it on one machine").
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "runtime/exercise_config.h"

namespace dt {

// `--hosts <none|lan|wan>` of dt_launch and dt_drill: replaces the exercise's [hosts] mode when
// given (non-empty). Throws std::invalid_argument naming the value otherwise.
void ApplyHostsOverride(ExerciseConfig& exercise, const std::string& mode);

// LCM's udpm URL at ttl=1 (added or replacing the URL's ttl): one hop, so off this host and onto
// the LAN, and never through a router. ttl=0 never leaves a host.
std::string HostsUdpmUrl(const std::string& url);
// The Cyclone DDS configuration of the hosts mode: interface dt0; on a LAN multicast discovery;
// on a WAN AllowMulticast false and unicast discovery to `peers` (every host's address).
std::string HostsCycloneConfig(HostsMode mode, const std::vector<std::string>& peers);

// Each process of the exercise runs in a network namespace of its own, a "host", whose one
// interface `dt0` (10.77.<site>.<host>) is a veth link to a port of its site's bridge; each
// bridge is in a namespace of its own. LAN: one bridge holds every host (mask /16, multicast
// crosses it). WAN: one bridge a site (mask /24), the sites joined by a router namespace
// (10.77.<site>.254 on each) that forwards unicast only. Every link's egress is shaped by
// `tc tbf` (rate_mbit, queue_ms); delay and jitter come from the processes' FaultyTransport.
// Every name carries the launcher's PID (`dt<pid>-<process>`), so launchers running at once never
// collide, and namespaces a killed launcher left behind are found and removed by the next one.
class HostNetwork {
 public:
  // Makes every host of the exercise. Throws std::runtime_error naming the command and what it
  // said if one fails (having removed what it made), if this process is not root, or if an
  // address does not fit (site 1..250, host 1..253).
  explicit HostNetwork(const ExerciseConfig& exercise);
  ~HostNetwork();  // removes every namespace it made (and with them links and bridges)
  HostNetwork(const HostNetwork&) = delete;
  HostNetwork& operator=(const HostNetwork&) = delete;

  // argv run on the process's host: "ip netns exec <namespace> argv..." (the program keeps the
  // PID it is started with, so signals reach it as before).
  std::vector<std::string> OnHost(const std::string& process, std::vector<std::string> argv) const;
  std::string Namespace(const std::string& process) const;
  std::string Address(const std::string& process) const;  // "10.77.1.2"

  // Cuts `side` off from `others`, for real: a single host's link goes down (`ip link set ...
  // down`); on a LAN several hosts move to a bridge of their own (processes named on neither
  // side stay with `others`). Throws std::runtime_error for several hosts across a WAN.
  void Cut(const std::vector<std::string>& side, const std::vector<std::string>& others);
  // Every link up and every port back on its site's bridge.
  void Heal();
  // SIGKILLs every process on the host (`ip netns pids`), escaped descendants included.
  void KillHost(const std::string& process) const;

  // The carrier URL the processes use on these hosts: udpm at ttl=1 (ttl=0 never leaves a host);
  // dds with a Cyclone DDS configuration written into `dir` for interface dt0 (multicast
  // discovery on a LAN; unicast to every host's address, AllowMulticast false, on a WAN). Throws
  // std::invalid_argument for memq, which cannot span hosts.
  std::string CarrierUrl(const std::string& url, const std::filesystem::path& dir) const;

  // Removes namespaces named dt<pid>-* whose launcher is no longer running, SIGKILLing the
  // processes left on them (a launcher killed by SIGKILL could not stop its children).
  static void RemoveStale();

 private:
  struct Host {
    std::string ns;    // network namespace
    std::string port;  // its bridge port, in the site's bridge namespace
    int site = 0;
    int host = 0;
  };
  std::string SiteNamespace(int site) const;
  void Make(const ExerciseConfig& exercise);
  void RemoveAll() noexcept;

  HostsMode mode_;
  std::string prefix_;  // "dt<pid>-"
  std::map<std::string, Host> hosts_;
  std::vector<int> sites_;
  std::vector<std::string> made_;  // namespaces, in the order made
  bool split_ = false;             // a LAN's second bridge holds a side of a partition
};

}  // namespace dt

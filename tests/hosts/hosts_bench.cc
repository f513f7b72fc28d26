// hosts_bench: the protocol across hosts (docs/performance.md, docs/deploy.md "Trying it on one
// machine"). Every replica is a process of its own on a host of its own: the network namespaces,
// bridges, tbf-shaped links and router of the hosts mode (launcher/host_network.h), made and
// removed by the bench itself inside a private network namespace it enters first.
//
//   hosts_bench lan [--carrier udpm|dds] [--bursts 200] [--burst 500] [--singles 1000]
//                   [--loss 0.01] [--rate-mbit 100]
//     node -> node features/s (bursts created on A until B has applied them) and the latency of
//     one change (created on A to applied on B), server, A and B on the hosts' LAN with `loss` on
//     receipt at every process, ÷ the same with the three on one loopback (no loss, no shaping).
//   hosts_bench wan [--features 100000] [--delay-ms 50] [--runs 5] [--playback-window-max N]
//     server and A on site 1, B on site 2 behind the router, Cyclone DDS with unicast discovery,
//     `delay_ms` between the sites: B's rejoin catch-up of `features` ÷ a raw transfer of as many
//     Construct messages between the same hosts over the same carrier and delay, in windows of
//     the playback window (256); then anti-entropy's detect, repair and settle times for `runs`
//     corruptions of B's copy of one of A's changes. `--playback-window-max 256`: the replicas'
//     catch-up window fixed at 256, as before it adapted (default: the protocol's).
//
// Root only. Peers are this program again (`hosts_bench --peer ...`, tests/hosts/bench_peer.h),
// started on their hosts with `ip netns exec` and stopped by PID. Every wait is bounded; the
// namespaces are removed at the end, on an error too (and a killed bench's by the next start).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "launcher/host_network.h"
#include "runtime/exercise_config.h"
#include "simulation/bench/lcm_cluster.h"
#include "tests/hosts/bench_peer.h"
#include "tests/hosts/peer_process.h"
#include "transport/test/private_netns.h"

namespace dt::hostsbench {
namespace {

constexpr int kStartMs = 30000;      // a peer's start (its transport up)
constexpr int kSignOnMs = 60000;     // sign-on, DDS discovery across a WAN included
constexpr int kStepMs = 60000;       // one burst, one change, one window of checks
constexpr int64_t kRawWindow = 256;  // ReplicaConfig::playback_window's default
const NodeAddress kServer{1, 100}, kA{1, 1};

std::string Self() { return std::filesystem::read_symlink("/proc/self/exe").string(); }

// The three replicas' exercise as the hosts mode reads it (names, addresses, [hosts]).
ExerciseConfig Exercise(const std::string& url, HostsMode mode, double rate_mbit, NodeAddress b,
                        const std::filesystem::path& dir) {
  const std::string toml =
      "[exercise]\nname = \"hosts-bench\"\nid = 1\ntransport = \"" + url + "\"\nrun_dir = \"" +
      dir.string() + "\"\n[auth]\nkey_file = \"" DT_SOURCE_DIR "/configs/keys/demo.key\"\n" +
      "[terrain]\nposts_per_side = 65\nspacing_m = 10.0\n[hosts]\nmode = \"" +
      std::string(HostsModeName(mode)) + "\"\nrate_mbit = " + std::to_string(rate_mbit) +
      "\n[server]\nname = \"server\"\nsite = 1\nhost = 100\n" +
      "[[node]]\nname = \"node-a\"\nsite = 1\nhost = 1\n[[node]]\nname = \"node-b\"\nsite = " +
      std::to_string(b.site) + "\nhost = " + std::to_string(b.host) + "\n";
  return ParseExerciseConfig(toml, "hosts_bench", dir);
}

// A temporary directory, removed with everything in it.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    char name[] = "/tmp/hosts_bench.XXXXXX";
    if (mkdtemp(name) == nullptr) throw std::runtime_error("mkdtemp failed");
    path = name;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

// The peers' hosts: a HostNetwork, or none (every peer on this loopback).
struct Hosts {
  std::unique_ptr<HostNetwork> net;
  std::string url;  // the carrier's URL on these hosts

  std::unique_ptr<PeerProcess> Start(const std::string& name, PeerOptions o) const {
    o.url = url;
    std::vector<std::string> argv{Self(), "--peer"};
    for (std::string& a : PeerArgs(o)) argv.push_back(std::move(a));
    if (net) argv = net->OnHost(name, argv);
    return std::make_unique<PeerProcess>(name, argv, kStartMs);
  }
};

PeerOptions Options(PeerKind kind, NodeAddress address, bool fast_ack, double loss,
                    int64_t delay_ms, int playback_window_max = 0) {
  PeerOptions o;
  o.playback_window_max = playback_window_max;
  o.kind = kind;
  o.address = address;
  o.fast_ack = fast_ack;
  o.drop_probability = loss;
  o.other_site_delay_ms = delay_ms;
  return o;
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const auto k = static_cast<size_t>(p * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

double Ms(int64_t ns) { return static_cast<double>(ns) / 1e6; }

struct LanFigures {
  double features_per_s = 0, p50_us = 0, p99_us = 0;
};

// Server, A and B on `hosts`: bursts of `burst` craters created on A until B has applied them,
// then `singles` craters one at a time, created on A to applied on B.
LanFigures NodeToNode(const Hosts& hosts, NodeAddress b_address, double loss, int bursts, int burst,
                      int singles) {
  auto server = hosts.Start("server", Options(PeerKind::kServer, kServer, true, loss, 0));
  auto a = hosts.Start("node-a", Options(PeerKind::kNode, kA, true, loss, 0));
  auto b = hosts.Start("node-b", Options(PeerKind::kNode, b_address, true, loss, 0));
  a->Ask("signed_on", kSignOnMs);
  b->Ask("signed_on", kSignOnMs);
  int64_t n = 0, engine_ns = 0;
  for (int i = 0; i < bursts; ++i) {
    const int done = b->Send("features " + std::to_string(n + burst));
    b->Ask("ping", kStepMs);  // B holds the wait before A creates anything
    const int64_t t0 = bench::SteadyNowNs();
    a->Ask("create " + std::to_string(n) + " " + std::to_string(burst), kStepMs);
    engine_ns += b->Wait(done, kStepMs).t_ns - t0;
    n += burst;
  }
  std::vector<double> latency_us;
  for (int i = 0; i < singles; ++i) {
    const int done = b->Send("features " + std::to_string(n + 1));
    b->Ask("ping", kStepMs);
    const Answer created = a->Ask("create " + std::to_string(n) + " 1", kStepMs);
    const int64_t first_ns = std::stoll(created.values.at(0));
    latency_us.push_back(static_cast<double>(b->Wait(done, kStepMs).t_ns - first_ns) / 1e3);
    ++n;
  }
  const std::string da = a->Ask("digest", kStepMs).values.at(0);
  const std::string db = b->Ask("digest", kStepMs).values.at(0);
  if (da != db) throw std::runtime_error("A and B hold different digests: " + da + ", " + db);
  LanFigures f;
  f.features_per_s = static_cast<double>(bursts) * burst / (static_cast<double>(engine_ns) / 1e9);
  f.p50_us = Percentile(latency_us, 0.50);
  f.p99_us = Percentile(latency_us, 0.99);
  return f;
}

std::string Value(const std::vector<std::string>& args, const std::string& flag,
                  const std::string& fallback) {
  for (size_t i = 0; i + 1 < args.size(); ++i) {
    if (args[i] == flag) return args[i + 1];
  }
  return fallback;
}

std::string DdsUrl(const std::string& config) { return "dds://0?config=" + config; }
constexpr const char* kUdpmLoopback = "udpm://239.255.76.67:7667?ttl=0";
const std::string kDdsLoopback = DdsUrl(DT_SOURCE_DIR "/configs/cyclonedds-loopback.xml");

int Lan(const std::vector<std::string>& args) {
  const std::string carrier = Value(args, "--carrier", "udpm");
  const int bursts = std::stoi(Value(args, "--bursts", "200"));
  const int burst = std::stoi(Value(args, "--burst", "500"));
  const int singles = std::stoi(Value(args, "--singles", "1000"));
  const double loss = std::stod(Value(args, "--loss", "0.01"));
  const double rate_mbit = std::stod(Value(args, "--rate-mbit", "100"));
  if (carrier != "udpm" && carrier != "dds") {
    throw std::invalid_argument("--carrier " + carrier + ": udpm or dds");
  }
  const std::string url = carrier == "udpm" ? kUdpmLoopback : kDdsLoopback;
  const NodeAddress b{1, 2};

  Hosts loopback{nullptr, url};
  const LanFigures one = NodeToNode(loopback, b, 0.0, bursts, burst, singles);
  std::printf("loopback %s: %.0f features/s, latency p50 %.0f us, p99 %.0f us\n", carrier.c_str(),
              one.features_per_s, one.p50_us, one.p99_us);

  TempDir dir;
  Hosts lan;
  lan.net = std::make_unique<HostNetwork>(Exercise(url, HostsMode::kLan, rate_mbit, b, dir.path));
  lan.url = lan.net->CarrierUrl(url, dir.path);
  const LanFigures hosts = NodeToNode(lan, b, loss, bursts, burst, singles);
  std::printf(
      "lan %s (%g Mbit/s tbf, %g %% loss): %.0f features/s, latency p50 %.0f us, p99 "
      "%.0f us\n",
      carrier.c_str(), rate_mbit, loss * 100, hosts.features_per_s, hosts.p50_us, hosts.p99_us);
  std::printf("lan / loopback: features/s %.2f, latency p50 %.2f, p99 %.2f\n",
              hosts.features_per_s / one.features_per_s, hosts.p50_us / one.p50_us,
              hosts.p99_us / one.p99_us);
  return 0;
}

int Wan(const std::vector<std::string>& args) {
  const int64_t n = std::stoll(Value(args, "--features", "100000"));
  const int64_t delay_ms = std::stoll(Value(args, "--delay-ms", "50"));
  const int runs = std::stoi(Value(args, "--runs", "5"));
  const int window_max = std::stoi(Value(args, "--playback-window-max", "0"));
  const NodeAddress b_address{2, 1};
  const auto big_ms = static_cast<int>(std::max<int64_t>(kStepMs, 3 * n));  // 3 ms a feature

  TempDir dir;
  Hosts wan;
  wan.net = std::make_unique<HostNetwork>(
      Exercise(kDdsLoopback, HostsMode::kWan, 100.0, b_address, dir.path));
  wan.url = wan.net->CarrierUrl(kDdsLoopback, dir.path);

  // Rejoin: B signs on and crashes; A creates n craters, the server stores them; B restarts with
  // no state and is timed from its start until it holds them all.
  auto server =
      wan.Start("server", Options(PeerKind::kServer, kServer, false, 0, delay_ms, window_max));
  auto a = wan.Start("node-a", Options(PeerKind::kNode, kA, false, 0, delay_ms, window_max));
  auto b = wan.Start("node-b", Options(PeerKind::kNode, b_address, false, 0, delay_ms, window_max));
  a->Ask("signed_on", kSignOnMs);
  b->Ask("signed_on", kSignOnMs);
  b->Kill();
  a->Ask("create 0 " + std::to_string(n), big_ms);
  server->Ask("features " + std::to_string(n), big_ms);
  b = wan.Start("node-b", Options(PeerKind::kNode, b_address, false, 0, delay_ms, window_max));
  const int64_t catch_up_ns =
      b->Ask("features " + std::to_string(n), big_ms).t_ns - b->started_ns();
  b->Ask("settled", big_ms);
  const std::string digest = server->Ask("digest", kStepMs).values.at(0);
  for (PeerProcess* p : {a.get(), b.get()}) {
    const std::string d = p->Ask("digest", kStepMs).values.at(0);
    if (d != digest) throw std::runtime_error(p->name() + "'s digest " + d + " != " + digest);
  }
  std::printf("wan dds (%lld ms between sites): rejoin catch-up of %lld features %.0f ms\n",
              static_cast<long long>(delay_ms), static_cast<long long>(n), Ms(catch_up_ns));

  // Anti-entropy: B's copy of one of A's changes corrupted at moments spread over the summary
  // period; detect = until any replica knows, repair = until B holds the right copy again,
  // settle = until none is diverged and every one caught up.
  std::vector<double> detect, repair, settle;
  for (int run = 1; run <= runs; ++run) {
    // A deliberate spread of the moment within the 1 s summary period, not a synchronisation.
    std::this_thread::sleep_for(std::chrono::milliseconds((run * 259) % 1000));
    const std::string change = "1 1 " + std::to_string(n * run / (runs + 1));
    std::vector<std::pair<PeerProcess*, int>> diverged;
    for (PeerProcess* p : {server.get(), a.get(), b.get()}) {
      diverged.emplace_back(p, p->Send("diverged"));
    }
    for (auto& wait : diverged) wait.first->Ask("ping", kStepMs);  // the waits are held
    const int64_t t0 = b->Ask("corrupt " + change, kStepMs).t_ns;
    const int64_t t1 = WaitFirst(diverged, kStepMs).second.t_ns;
    const int64_t t2 = b->Ask("repaired " + change, kStepMs).t_ns;
    int64_t t3 = t2;
    for (PeerProcess* p : {server.get(), a.get(), b.get()}) {
      t3 = std::max(t3, p->Ask("settled", kStepMs).t_ns);
    }
    detect.push_back(Ms(t1 - t0));
    repair.push_back(Ms(t2 - t0));
    settle.push_back(Ms(t3 - t0));
    std::printf("  anti-entropy run %d: detect %.0f ms, repair %.0f ms, settle %.0f ms\n", run,
                detect.back(), repair.back(), settle.back());
  }
  for (PeerProcess* p : {a.get(), b.get()}) {
    const std::string d = p->Ask("digest", kStepMs).values.at(0);
    if (d != digest) {
      throw std::runtime_error(p->name() + "'s digest after the repairs " + d + " != " + digest);
    }
  }
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  };
  auto max = [](const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  };
  server.reset();
  a.reset();
  b.reset();

  // Raw: as many Construct messages from A's host to B's over the same carrier and delay, in
  // windows of 256 each acknowledged before the next.
  auto recv = wan.Start("node-b", Options(PeerKind::kRawRecv, b_address, false, 0, delay_ms));
  auto send = wan.Start("node-a", Options(PeerKind::kRawSend, kA, false, 0, delay_ms));
  send->Ask("hello", kSignOnMs);
  const int received = recv->Send("recv " + std::to_string(n) + " " + std::to_string(kRawWindow));
  recv->Ask("ping", kStepMs);
  const Answer sent =
      send->Ask("send " + std::to_string(n) + " " + std::to_string(kRawWindow), big_ms);
  const int64_t raw_ns = recv->Wait(received, kStepMs).t_ns - std::stoll(sent.values.at(0));
  std::printf("wan dds raw transfer of %lld Construct messages in windows of %lld: %.0f ms\n",
              static_cast<long long>(n), static_cast<long long>(kRawWindow), Ms(raw_ns));
  std::printf("wan rejoin catch-up / raw: %.2f\n",
              static_cast<double>(catch_up_ns) / static_cast<double>(raw_ns));
  std::printf(
      "wan anti-entropy (%d runs): detect mean %.0f ms, max %.0f ms; repair mean %.0f "
      "ms, max %.0f ms; settle mean %.0f ms, max %.0f ms\n",
      runs, mean(detect), max(detect), mean(repair), max(repair), mean(settle), max(settle));
  return 0;
}

}  // namespace
}  // namespace dt::hostsbench

int main(int argc, char** argv) {
  using namespace dt::hostsbench;
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (!args.empty() && args[0] == "--peer") {
      return RunPeer(ParsePeerArgs({args.begin() + 1, args.end()}));
    }
    if (args.empty() || (args[0] != "lan" && args[0] != "wan")) {
      std::fprintf(stderr, "usage: hosts_bench lan|wan [options] (see its source's head)\n");
      return 2;
    }
    if (geteuid() != 0) {
      std::fprintf(stderr, "hosts_bench: the hosts mode needs root (network namespaces)\n");
      return 2;
    }
    dt::testing::EnterPrivateNetns(argc, argv);
    if (auto reason = dt::testing::NetnsSkipReason()) {
      std::fprintf(stderr, "hosts_bench: no private network namespace: %s\n", reason->c_str());
      return 2;
    }
    dt::HostNetwork::RemoveStale();
    return args[0] == "lan" ? Lan(args) : Wan(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hosts_bench: %s\n", e.what());
    return 1;
  }
}

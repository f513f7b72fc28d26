#include "tests/hosts/bench_peer.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "engine/memory_change_store.h"
#include "engine/replica.h"
#include "simulation/bench/lcm_cluster.h"
#include "transport/faulty_transport.h"
#include "transport/pdu_bus.h"
#include "transport/transport.h"

namespace dt::hostsbench {
namespace {

// The raw peers' channels carry another exercise ID than the replicas', so the two never meet.
constexpr uint8_t kRawExercise = 2;

const char* KindName(PeerKind k) {
  switch (k) {
    case PeerKind::kServer:
      return "server";
    case PeerKind::kNode:
      return "node";
    case PeerKind::kRawSend:
      return "raw-send";
    case PeerKind::kRawRecv:
      return "raw-recv";
  }
  return "?";
}

int64_t NowMs() { return bench::SteadyNowNs() / 1000000; }

void Reply(const std::string& id, const std::string& rest) {
  std::printf("%s %s\n", id.c_str(), rest.c_str());
  std::fflush(stdout);
}

std::string Ok(int64_t t_ns, const std::string& values = "") {
  return "ok " + std::to_string(t_ns) + (values.empty() ? "" : " " + values);
}

// A command waiting for its condition: true when done (it has replied).
using Step = std::function<bool()>;

// Reads whole lines from stdin without blocking the loop; false at end of input.
class LineReader {
 public:
  bool Read(std::vector<std::string>& lines) {
    char buf[4096];
    const ssize_t n = read(STDIN_FILENO, buf, sizeof buf);
    if (n <= 0) return false;
    pending_.append(buf, static_cast<size_t>(n));
    for (size_t nl; (nl = pending_.find('\n')) != std::string::npos;) {
      lines.push_back(pending_.substr(0, nl));
      pending_.erase(0, nl + 1);
    }
    return true;
  }

 private:
  std::string pending_;
};

// The loop every peer runs: wait up to 1 ms for traffic or a command (none while traffic flows),
// read commands, dispatch inside one batch, tick, run the steps (as a process's tick).
class Peer {
 public:
  explicit Peer(const PeerOptions& o) : options_(o) {
    FaultConfig faults;
    faults.drop_probability = o.drop_probability;
    faults.other_site_min_delay = o.other_site_delay_ms;
    faults.other_site_max_delay = o.other_site_delay_ms;
    const bool raw = o.kind == PeerKind::kRawSend || o.kind == PeerKind::kRawRecv;
    transport_ = std::make_unique<FaultyTransport>(
        MakeTransport(o.url, raw ? kRawExercise : bench::kBenchExercise), o.address, faults,
        (uint64_t{o.address.site} << 16) + o.address.host, DelayUnit::kMilliseconds);
  }
  virtual ~Peer() = default;
  Peer(const Peer&) = delete;
  Peer& operator=(const Peer&) = delete;

  int Run() {
    Reply("0", Ok(bench::SteadyNowNs()));
    LineReader reader;
    bool busy = false;
    while (true) {
      pollfd fds[2] = {{transport_->Fd(), POLLIN, 0}, {STDIN_FILENO, POLLIN, 0}};
      (void)poll(fds, 2, busy ? 0 : 1);
      if ((fds[1].revents & (POLLIN | POLLHUP)) != 0) {
        std::vector<std::string> lines;
        if (!reader.Read(lines)) return 0;  // the driver is gone
        for (const std::string& line : lines) {
          std::istringstream in(line);
          std::string id, verb;
          in >> id >> verb;
          if (verb == "quit") return 0;
          std::optional<Step> step = Command(id, verb, in);
          if (!step) {
            Reply(id, std::string("error unknown command for a ") + KindName(options_.kind) + ": " +
                          line);
          } else {
            steps_.push_back(std::move(*step));
          }
        }
      }
      const int dispatched = Round();
      for (auto it = steps_.begin(); it != steps_.end();) it = (*it)() ? steps_.erase(it) : ++it;
      busy = dispatched > 0;
    }
  }

 protected:
  // The step for a command, or nullopt for one this peer does not know.
  virtual std::optional<Step> Command(const std::string& id, const std::string& verb,
                                      std::istream& args) = 0;
  // One round: dispatch what arrived (and tick); the messages dispatched.
  virtual int Round() = 0;

  PeerOptions options_;
  std::unique_ptr<FaultyTransport> transport_;
  std::list<Step> steps_;
};

class ReplicaPeer final : public Peer {
 public:
  explicit ReplicaPeer(const PeerOptions& o)
      : Peer(o),
        ground_(bench::BenchGround()),
        bus_(*transport_, bench::BenchBusConfig(o.address, ground_)) {
    ReplicaConfig rc = o.fast_ack ? bench::FastAckConfig() : ReplicaConfig{};
    if (o.playback_window_max > 0) rc.playback_window_max = o.playback_window_max;
    rc.address = o.address;
    rc.role = o.kind == PeerKind::kServer ? NodeRole::kServer : NodeRole::kNode;
    if (o.kind == PeerKind::kServer) rc.store = &store_;
    replica_ = std::make_unique<Replica>(rc, ground_, bus_);
    replica_->SignOn(NowMs());
  }

 private:
  int Round() override {
    PduBus::Batch batch(bus_);
    const Result<int> dispatched = bus_.HandleTimeout(0);
    replica_->Tick(NowMs());
    return dispatched ? dispatched.value() : 0;
  }

  std::optional<Step> Command(const std::string& id, const std::string& verb,
                              std::istream& args) override {
    Replica& r = *replica_;
    auto when = [id](std::function<bool()> done) -> Step {
      return [id, done = std::move(done)] {
        if (!done()) return false;
        Reply(id, Ok(bench::SteadyNowNs()));
        return true;
      };
    };
    if (verb == "ping") return when([] { return true; });
    if (verb == "signed_on") return when([&r] { return r.signed_on(); });
    if (verb == "diverged") return when([&r] { return r.diverged(); });
    if (verb == "settled") return when([&r] { return !r.diverged() && r.caught_up(); });
    if (verb == "features") {
      size_t n = 0;
      args >> n;
      return when([&r, n] { return r.live_feature_count() >= n; });
    }
    if (verb == "digest") {
      return Step([id, &r] {
        Reply(id, Ok(bench::SteadyNowNs(), r.Digest()));
        return true;
      });
    }
    if (verb == "create") {
      // Craters first..first+count-1; a full window (not acknowledged yet) waits for the next
      // round. Replies with the time the last was created and the time the first was.
      int64_t first = 0, count = 0;
      args >> first >> count;
      auto next = std::make_shared<int64_t>(first);
      auto first_ns = std::make_shared<int64_t>(0);
      return Step([id, &r, next, first_ns, end = first + count] {
        while (*next < end) {
          auto created = r.Create(bench::BenchCrater(*next));
          if (!created) {
            if (created.error().message.find("not acknowledged") != std::string::npos) {
              return false;
            }
            Reply(id, "error " + created.error().message);
            return true;
          }
          if (*first_ns == 0) *first_ns = bench::SteadyNowNs();
          ++*next;
        }
        Reply(id, Ok(bench::SteadyNowNs(), std::to_string(*first_ns)));
        return true;
      });
    }
    if (verb == "corrupt" || verb == "repaired") {
      // corrupt: this replica's copy of the author's change `seq` gets a crater radius 1 m
      // larger, as a damaged store would give it; repaired: done when the copy is the one before
      // again.
      NodeAddress author;
      int64_t seq = 0;
      args >> author.site >> author.host >> seq;
      const ChangeLog* log = r.log(author);
      const Change* held = log ? log->Find(seq) : nullptr;
      if (held == nullptr) {
        return Step([id] {
          Reply(id, "error the change to corrupt is not held");
          return true;
        });
      }
      if (verb == "corrupt") {
        good_[{author, seq}] = *held;
        Change bad = *held;
        bad.params.length_m[0] += 1.0;
        const int64_t t = bench::SteadyNowNs();
        const Status s = r.anti_entropy().Overwrite(bad);
        return Step([id, t, ok = s.ok()] {
          Reply(id, ok ? Ok(t) : "error Overwrite refused the change");
          return true;
        });
      }
      const Change good = good_[{author, seq}];
      return when([&r, author, seq, good] {
        const ChangeLog* l = r.log(author);
        const Change* c = l ? l->Find(seq) : nullptr;
        return c != nullptr && *c == good;
      });
    }
    return std::nullopt;
  }

  HeightGrid ground_;
  PduBus bus_;
  MemoryChangeStore store_;
  std::unique_ptr<Replica> replica_;
  std::map<std::pair<NodeAddress, int64_t>, Change> good_;
};

// Raw transfer: Construct-sized messages straight on the carrier (through the same
// fault-injecting transport, so with the same WAN delay), no engine. The sender publishes a
// window, the receiver acknowledges each full window, then the next goes (as the playback
// window does).
class RawPeer final : public Peer {
 public:
  explicit RawPeer(const PeerOptions& o)
      : Peer(o),
        data_(bench::BenchConstructBytes(kRawDataOrigin)),
        ack_(bench::BenchConstructBytes(kRawAckOrigin)),
        ping_(bench::BenchConstructBytes(kRawPingOrigin)),
        pong_(bench::BenchConstructBytes(kRawPongOrigin)) {
    transport_->Subscribe(PduType::kConstruct, [this](std::span<const uint8_t> b) {
      const std::vector<uint8_t> bytes(b.begin(), b.end());
      if (bytes == data_) {
        ++received_;
        if (received_ == expect_ || (window_ > 0 && received_ % window_ == 0)) ++acks_due_;
      } else if (bytes == ack_) {
        ++acks_;
      } else if (bytes == ping_) {
        ++pongs_due_;
      } else if (bytes == pong_) {
        ++pongs_;
      }
    });
  }

 private:
  void Send(const std::vector<uint8_t>& bytes) {
    if (!transport_->Publish(PduType::kConstruct, bytes).ok()) failed_ = true;
  }

  int Round() override {
    const Result<int> dispatched = transport_->HandleTimeout(0);
    // Answers go out of the handler, after the dispatch.
    for (; acks_due_ > 0; --acks_due_) Send(ack_);
    for (; pongs_due_ > 0; --pongs_due_) Send(pong_);
    return dispatched ? dispatched.value() : 0;
  }

  std::optional<Step> Command(const std::string& id, const std::string& verb,
                              std::istream& args) override {
    if (verb == "ping") {
      return Step([id] {
        Reply(id, Ok(bench::SteadyNowNs()));
        return true;
      });
    }
    if (verb == "hello" && options_.kind == PeerKind::kRawSend) {
      // Until the receiver answers (discovery may take a while on DDS), one ping every 20 ms.
      auto last_ms = std::make_shared<int64_t>(-1000);
      return Step([this, id, last_ms] {
        if (pongs_ > 0) {
          Reply(id, Ok(bench::SteadyNowNs()));
          return true;
        }
        if (NowMs() - *last_ms >= 20) {
          Send(ping_);
          *last_ms = NowMs();
        }
        return false;
      });
    }
    int64_t n = 0, window = 0;
    args >> n >> window;
    if (verb == "recv" && options_.kind == PeerKind::kRawRecv) {
      received_ = 0;
      expect_ = n;
      window_ = window;
      return Step([this, id, n] {
        if (received_ < n) return false;
        Reply(id, Ok(bench::SteadyNowNs()));
        return true;
      });
    }
    if (verb == "send" && options_.kind == PeerKind::kRawSend) {
      acks_ = 0;
      auto sent = std::make_shared<int64_t>(0);
      auto first_ns = std::make_shared<int64_t>(0);
      return Step([this, id, n, window, sent, first_ns] {
        if (failed_) {
          Reply(id, "error a publish failed");
          return true;
        }
        // Window k goes once the receiver acknowledged window k - 1.
        if (*sent < n && acks_ * window >= *sent) {
          if (*first_ns == 0) *first_ns = bench::SteadyNowNs();
          const int64_t end = std::min(n, *sent + window);
          for (; *sent < end; ++*sent) Send(data_);
        }
        const int64_t windows = (n + window - 1) / window;
        if (acks_ < windows) return false;
        Reply(id, Ok(bench::SteadyNowNs(), std::to_string(*first_ns)));
        return true;
      });
    }
    return std::nullopt;
  }

  std::vector<uint8_t> data_, ack_, ping_, pong_;
  int64_t received_ = 0, expect_ = 0, window_ = 0, acks_ = 0, pongs_ = 0;
  int acks_due_ = 0, pongs_due_ = 0;
  bool failed_ = false;
};

PeerKind ParseKind(const std::string& s) {
  for (PeerKind k : {PeerKind::kServer, PeerKind::kNode, PeerKind::kRawSend, PeerKind::kRawRecv}) {
    if (s == KindName(k)) return k;
  }
  throw std::invalid_argument("hosts_bench --peer: unknown kind " + s);
}

}  // namespace

std::vector<std::string> PeerArgs(const PeerOptions& o) {
  return {KindName(o.kind),
          o.url,
          std::to_string(o.address.site),
          std::to_string(o.address.host),
          o.fast_ack ? "1" : "0",
          std::to_string(o.drop_probability),
          std::to_string(o.other_site_delay_ms),
          std::to_string(o.playback_window_max)};
}

PeerOptions ParsePeerArgs(const std::vector<std::string>& args) {
  if (args.size() != 8) {
    throw std::invalid_argument("hosts_bench --peer: 8 arguments expected, got " +
                                std::to_string(args.size()));
  }
  PeerOptions o;
  o.kind = ParseKind(args[0]);
  o.url = args[1];
  o.address = {static_cast<uint16_t>(std::stoi(args[2])),
               static_cast<uint16_t>(std::stoi(args[3]))};
  o.fast_ack = args[4] == "1";
  o.drop_probability = std::stod(args[5]);
  o.other_site_delay_ms = std::stoll(args[6]);
  o.playback_window_max = std::stoi(args[7]);
  return o;
}

int RunPeer(const PeerOptions& options) {
  std::unique_ptr<Peer> peer;
  if (options.kind == PeerKind::kServer || options.kind == PeerKind::kNode) {
    peer = std::make_unique<ReplicaPeer>(options);
  } else {
    peer = std::make_unique<RawPeer>(options);
  }
  return peer->Run();
}

}  // namespace dt::hostsbench

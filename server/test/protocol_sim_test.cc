// The deterministic simulation of the protocol: nodes, a server (sometimes a standby) over a
// SimNetwork with seeded loss, duplication, delay, reordering, partitions and crashes, then a
// healed network; checks the guarantee of docs/protocol.md after every schedule.
//
//   DT_SIM_SEEDS=<n>       seeds to run (default 1000), starting at DT_SIM_FIRST_SEED (default 1)
//   DT_SIM_SEED=<s>        run only seed s (reproduces a failure exactly)
//   DT_SIM_TRACE=1         print the schedule's events; DT_SIM_LOG=info the replicas' log lines
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "terrain/slump.h"

#include "engine/id_reservation.h"
#include "engine/memory_change_store.h"
#include "engine/record_store.h"
#include "engine/test/sim_cluster.h"
#include "log/log.h"
#include "pdu/conversion.h"
#include "pdu/pdu_bus.h"
#include "server/sqlite_change_store.h"
#include "terrain/terrain_digest.h"

namespace dt {
namespace {

using testing::SimCluster;

HeightGrid SimGround() { return HeightGrid(17, 8.0, 5.0f); }

constexpr NodeAddress kServer{1, 100};
constexpr NodeAddress kStandby{1, 101};
// A member that never runs: step "gone author" sends one change in its name.
constexpr NodeAddress kGhost{1, 9};
// An observer (a live view, docs/view.md): started a quarter of the way through, never crashed;
// nobody may wait for it, and it must end holding every change the server holds, identically.
constexpr NodeAddress kView{1, 50};
constexpr int kNodes = 3;
constexpr int kOps = 40;
constexpr int64_t kHealMs = 6000;

int64_t EnvInt(const char* name, int64_t fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::strtoll(v, nullptr, 10) : fallback;
}

class SimRun {
 public:
  SimRun(uint64_t seed, std::filesystem::path dir)
      : seed_(seed), rng_(seed), corrupt_rng_(seed ^ 0xA5A5A5A5u), dir_(std::move(dir)) {}

  // "" when the guarantee holds, otherwise what failed.
  std::string Run();
  // Virtual time the run covered (printed with the wall time, to size long runs).
  int64_t simulated_ms() const { return cluster_ != nullptr ? cluster_->now_ms() : 0; }

 private:
  uint64_t Next(uint64_t n) { return rng_() % n; }
  double Uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(rng_() >> 11) * 0x1.0p-53;
  }
  bool Chance(double p) { return Uniform(0, 1) < p; }

  Status StartServer(NodeAddress address, NodeRole role);
  void StartNode(NodeAddress address);
  void Crash(NodeAddress address);
  // Restarts every crashed replica whose downtime is over.
  Status RestartDue();
  FeatureParams RandomParams(FeatureType type);
  Status BladeOp(Replica& r);
  std::string Command(NodeAddress who);
  void RecordIssued(NodeAddress who, int64_t seq_before);
  void ObserveAcks();
  int64_t MaxAck(NodeAddress a) const {
    int64_t m = 0;
    for (const auto& [key, v] : max_ack_) {
      if (key.first == a) m = std::max(m, v);
    }
    return m;
  }
  // Crashes and partitions do not overlap: a crash only while the network is whole and every
  // replica is up, a partition only while every replica is up (docs/protocol.md, "Limits").
  bool AllUp() {
    if (!restart_at_ms_.empty() || partitioned_) return false;
    if (cluster_->now_ms() < blocked_until_ms_) return false;
    for (NodeAddress a : cluster_->live()) {
      if (!cluster_->at(a).signed_on()) return false;
    }
    return true;
  }
  std::string Check();
  // The observer's guarantee (docs/view.md "Limits"): every change the server holds, the same.
  std::string CheckObserver();
  int observer_extra_ = 0;  // changes only the observer holds (a lost change it alone got)

 public:
  int observer_extra() const { return observer_extra_; }

 private:
  // Step "anti-entropy": one slot corrupted on a random replica (not the server) mid-run must be
  // found and repaired by the end (docs/protocol.md, "Anti-entropy").
  void CorruptOneSlot();
  std::string CheckCorruptionRepaired();
  // Step "gone author": a member sends one change whose predecessors reach no one and is never
  // heard again (a node that crashed for good right after sending); the gap must be given up on
  // by the end, or every replica would wait for ever (docs/protocol.md, "Lost changes").
  void GhostSendsOneChange();

  uint64_t seed_;
  std::mt19937_64 rng_;
  // The corruption's own draws, so the rest of a seed's schedule is drawn as without it.
  std::mt19937_64 corrupt_rng_;
  struct Corruption {
    NodeAddress replica;
    NodeAddress author;
    int64_t seq = 0;
    int crashes = 0;  // the replica's crashes_ then: its object must still be the same
  };
  std::optional<Corruption> corruption_;
  std::map<NodeAddress, int> crashes_;
  std::filesystem::path dir_;
  std::unique_ptr<SimCluster> cluster_;
  // On cluster_'s network, so declared after it (destroyed first).
  std::unique_ptr<Transport> ghost_transport_;
  std::unique_ptr<PduBus> ghost_bus_;
  std::optional<Change> ghost_change_;
  bool use_sqlite_ = false;
  bool with_standby_ = false;
  std::map<NodeAddress, std::unique_ptr<ChangeStore>> stores_;
  std::map<NodeAddress, std::unique_ptr<MemoryChangeStore>> memory_stores_;
  // Each node's feature number reservation, which survives its crashes as a file would.
  std::map<NodeAddress, std::unique_ptr<MemoryIdReservation>> reservations_;
  std::map<NodeAddress, int64_t> restart_at_ms_;
  std::map<NodeAddress, int> incarnation_;
  struct Issued {
    Change change;
    int incarnation;
    bool replaced;  // its sequence was reused after it was lost
  };
  std::vector<Issued> issued_;
  std::set<std::pair<NodeAddress, int64_t>> issued_seqs_;
  std::set<FeatureId> issued_ids_;
  std::vector<FeatureId> ids_;
  std::map<std::pair<NodeAddress, int>, int64_t> max_ack_;
  std::string failure_;
  bool partitioned_ = false;
  // Until then a node's or the standby's writes fail: like a partition, no crash meanwhile (a
  // replica nobody hears during a sign-on is the double fault of docs/protocol.md "Limits").
  int64_t blocked_until_ms_ = 0;
  bool trace_ = std::getenv("DT_SIM_TRACE") != nullptr;
};

Status SimRun::StartServer(NodeAddress address, NodeRole role) {
  ChangeStore* store = nullptr;
  if (use_sqlite_) {
    // Reopened on every restart, as a restarted process would.
    stores_.erase(address);
    auto s = SqliteChangeStore::Open(dir_ / fmt::format("server-{}.db", address.host),
                                     SimGround().size_m());
    if (!s) return s.error();
    stores_[address] = std::move(s).value();
    store = stores_[address].get();
  } else {
    auto& m = memory_stores_[address];
    if (!m) m = std::make_unique<MemoryChangeStore>();
    store = m.get();
  }
  Replica& r = cluster_->Start(address, role, store);
  if (!r.load_status()) return r.load_status();
  return Status::Ok();
}

void SimRun::StartNode(NodeAddress address) {
  if (trace_) {
    std::printf("t=%lld start %s\n", static_cast<long long>(cluster_->now_ms()),
                address.ToString().c_str());
  }
  ++incarnation_[address];
  auto& ids = reservations_[address];
  if (!ids) ids = std::make_unique<MemoryIdReservation>();
  cluster_->Start(address, NodeRole::kNode, nullptr, ids.get());
}

void SimRun::Crash(NodeAddress address) {
  if (trace_) {
    std::printf("t=%lld crash %s\n", static_cast<long long>(cluster_->now_ms()),
                address.ToString().c_str());
    for (NodeAddress a : cluster_->live()) {
      std::string held;
      if (const ChangeLog* l = cluster_->at(a).log(address)) {
        for (const Change* c : l->Range(1, l->max_held())) {
          held += fmt::format(" {}@{}", c->stamp.change_seq, c->stamp.lamport);
        }
      }
      std::printf("   %s holds%s\n", a.ToString().c_str(), held.c_str());
    }
  }
  cluster_->Crash(address);
  ++crashes_[address];
  if (use_sqlite_) stores_.erase(address);
  restart_at_ms_[address] = cluster_->now_ms() + 200 + static_cast<int64_t>(Next(1500));
}

Status SimRun::RestartDue() {
  for (auto it = restart_at_ms_.begin(); it != restart_at_ms_.end();) {
    if (it->second > cluster_->now_ms()) {
      ++it;
      continue;
    }
    const NodeAddress a = it->first;
    it = restart_at_ms_.erase(it);
    if (a == kServer || a == kStandby) {
      if (Status s = StartServer(a, a == kServer ? NodeRole::kServer : NodeRole::kStandby); !s) {
        return s;
      }
    } else {
      StartNode(a);
    }
  }
  return Status::Ok();
}

FeatureParams SimRun::RandomParams(FeatureType type) {
  const double x = Uniform(15, 113), z = Uniform(15, 113);
  switch (type) {
    case FeatureType::kCrater: {
      // Half of them below the ground. Draws are sequenced (argument order is unspecified).
      const double r = Uniform(1, 6);
      const double depth = Next(2) == 0 ? 0.0 : Uniform(0.5, 2);
      return FeatureParams::DeepCrater(x, z, r, depth);
    }
    case FeatureType::kDitch: {
      std::vector<FeaturePoint> pts{{x, z, Uniform(1, 2), 4}};
      pts.push_back({x + Uniform(5, 10), z + Uniform(-3, 3), Uniform(1, 2), 5});
      pts.push_back({pts[1].x_m + Uniform(5, 10), pts[1].z_m + Uniform(3, 8), Uniform(1, 2), 4});
      const bool spoil = Next(2) == 0;
      return FeatureParams::Ditch(std::move(pts), 1.0, spoil ? 1.0 : 0.0, spoil ? 2.0 : 0.0);
    }
    case FeatureType::kBermLine: {
      std::vector<FeaturePoint> pts{{x, z, Uniform(1, 2), 4}};
      pts.push_back({x + Uniform(-8, 8), z + Uniform(5, 10), Uniform(1, 3), 5});
      return FeatureParams::BermLine(std::move(pts));
    }
    case FeatureType::kArea: {
      std::vector<FeaturePoint> pts{{x, z, 0, 0}};
      pts.push_back({x + Uniform(5, 10), z, 0, 0});
      pts.push_back({x + Uniform(0, 5), z + Uniform(5, 10), 0, 0});
      const bool water = Next(2) == 0;
      return FeatureParams::Area(std::move(pts), water ? Material::kWater : Material::kMud,
                                 water ? Uniform(0, 5) : 0.0);
    }
    case FeatureType::kBerm:
      return FeatureParams::Berm(x, z, Uniform(0, 6.28), Uniform(8, 30), Uniform(2, 5),
                                 Uniform(1, 3));
    case FeatureType::kBridge:
      return FeatureParams::Bridge(x, z, Uniform(0, 6.28), 4, Uniform(3, 5), Uniform(8, 16),
                                   Uniform(3, 5), Uniform(2, 3), Uniform(2, 3));
    case FeatureType::kEarthMove:
      return FeatureParams::EarthMove(
          {{static_cast<uint16_t>(Next(17)), static_cast<uint16_t>(Next(17)),
            static_cast<int32_t>(Uniform(-800, 800)) | 1}});
  }
  std::abort();
}

// Earth moves the simulation's blade operations issued, over every seed run.
int64_t earth_moves_issued = 0;

Status SimRun::BladeOp(Replica& r) {
  // A blade's work in miniature: soil cut from one post and piled on a neighbour, slumped to the
  // angle of repose on this replica's terrain, sent as earth moves.
  const HeightGrid& g = r.terrain().ground();
  const int i = 1 + static_cast<int>(Next(static_cast<uint64_t>(g.posts_per_side() - 2)));
  const int j = 1 + static_cast<int>(Next(static_cast<uint64_t>(g.posts_per_side() - 2)));
  PostWindow w(r.terrain(), i - 4, j - 4, 9, 9);
  const auto cut = static_cast<int64_t>(Uniform(100, 3000));
  w.height_mm(i, j) -= cut;
  w.height_mm(Next(2) == 0 ? i + 1 : i, Next(2) == 0 ? j - 1 : j + 1) += cut;
  Slump(w, [](Material) { return 35.0 * 3.14159265358979 / 180.0; });
  for (const auto& piece : SplitEarthMove(w.Deltas())) {
    if (auto id = r.Create(FeatureParams::EarthMove(piece)); !id) return id.error();
    ++earth_moves_issued;
  }
  return Status::Ok();
}

void SimRun::RecordIssued(NodeAddress who, int64_t seq_before) {
  Replica& r = cluster_->at(who);
  for (int64_t s = seq_before + 1; s <= r.own_change_seq(); ++s) {
    const Change* c = r.log(who)->Find(s);
    if (c == nullptr) {
      failure_ = fmt::format("node {} issued change {} but does not hold it", who.ToString(), s);
      return;
    }
    if (!issued_seqs_.insert({who, s}).second) {
      // A restarted node may reuse the sequence of a change that was never acknowledged (it
      // learns only what the server and its peers hold); an acknowledged one, never.
      if (s <= MaxAck(who)) {
        failure_ =
            fmt::format("acknowledged change sequence {}:{} issued twice", who.ToString(), s);
        return;
      }
      for (Issued& old : issued_) {
        if (old.change.author() == who && old.change.stamp.change_seq == s) old.replaced = true;
      }
    }
    issued_.push_back({*c, incarnation_[who], false});
    if (trace_) {
      std::printf("t=%lld issue %s:%lld lamport %llu id %s kind %d\n",
                  static_cast<long long>(cluster_->now_ms()), who.ToString().c_str(),
                  static_cast<long long>(s), static_cast<unsigned long long>(c->stamp.lamport),
                  c->id.ToString().c_str(), static_cast<int>(c->kind));
    }
    if (c->kind == ChangeKind::kConstruct) {
      if (!issued_ids_.insert(c->id).second) {
        failure_ = fmt::format("feature ID {} issued twice", c->id.ToString());
        return;
      }
      ids_.push_back(c->id);
    }
  }
}

std::string SimRun::Command(NodeAddress who) {
  Replica& r = cluster_->at(who);
  if (!r.signed_on()) return "";
  const int64_t before = r.own_change_seq();
  const uint64_t pick = Next(100);
  auto random_id = [&]() -> std::optional<FeatureId> {
    if (ids_.empty()) return std::nullopt;
    return ids_[Next(ids_.size())];
  };
  if (pick < 45 || ids_.empty()) {
    const uint64_t t = Next(100);
    if (t >= 70) {
      (void)BladeOp(r);  // blade work, as a bulldozer's tick makes it
    } else {
      const FeatureType type = t < 30   ? FeatureType::kCrater
                               : t < 44 ? FeatureType::kBerm
                               : t < 53 ? FeatureType::kBridge
                               : t < 60 ? FeatureType::kDitch
                               : t < 65 ? FeatureType::kBermLine
                                        : FeatureType::kArea;
      (void)r.Create(RandomParams(type));
    }
  } else if (pick < 70) {
    const FeatureId id = *random_id();
    const Record* rec = r.records().Find(id);
    const FeatureType type = rec != nullptr ? rec->params.type : FeatureType::kCrater;
    (void)r.Modify(id, RandomParams(type));
  } else if (pick < 85) {
    (void)r.Destroy(*random_id());
  } else {
    (void)r.Breach(*random_id(), Uniform(1, 8), Uniform(1, 4));
  }
  RecordIssued(who, before);
  return failure_;
}

void SimRun::ObserveAcks() {
  for (NodeAddress a : cluster_->live()) {
    if (a == kServer || a == kStandby) continue;
    // Acknowledgements count for the incarnation that saw them: a later one's may cover voids.
    auto& m = max_ack_[{a, incarnation_[a]}];
    if (trace_ && cluster_->at(a).acknowledged_change_seq() > m) {
      std::printf("t=%lld %s acknowledged up to %lld\n", static_cast<long long>(cluster_->now_ms()),
                  a.ToString().c_str(),
                  static_cast<long long>(cluster_->at(a).acknowledged_change_seq()));
    }
    m = std::max(m, cluster_->at(a).acknowledged_change_seq());
  }
}

std::string SimRun::Run() {
  use_sqlite_ = seed_ % 10 == 3;
  with_standby_ = seed_ % 4 == 1;
  FaultConfig faults;
  faults.drop_probability = Uniform(0, 0.3);
  faults.duplicate_probability = Uniform(0, 0.1);
  faults.min_delay = 0;
  faults.max_delay = static_cast<int64_t>(Next(40));
  faults.reorder_probability = Uniform(0, 0.2);
  faults.reorder_window = 50;
  ReplicaConfig rc;
  rc.max_feature_period_ms = 200;
  rc.silence_ms = 800;
  rc.playback_retry_ms = 300;
  rc.playback_window = 16;
  // Longer than any partition or downtime below, so only the gone author's gap is given up on.
  rc.gap_give_up_ms = 4000;
  std::vector<NodeAddress> nodes;
  for (int i = 1; i <= kNodes; ++i) nodes.push_back({1, static_cast<uint16_t>(i)});
  // Membership as an exercise file gives it (docs/protocol.md, "Rules for what is believed").
  rc.members[kServer] = NodeRole::kServer;
  if (with_standby_) rc.members[kStandby] = NodeRole::kStandby;
  for (NodeAddress a : nodes) rc.members[a] = NodeRole::kNode;
  rc.members[kGhost] = NodeRole::kNode;
  rc.members[kView] = NodeRole::kObserver;
  cluster_ = std::make_unique<SimCluster>(seed_, SimGround(), rc, faults);

  if (auto s = StartServer(kServer, NodeRole::kServer); !s) return s.error().message;
  if (with_standby_) {
    if (auto s = StartServer(kStandby, NodeRole::kStandby); !s) return s.error().message;
  }
  for (NodeAddress a : nodes) StartNode(a);

  for (int op = 0; op < kOps; ++op) {
    cluster_->Run(10 + 10 * static_cast<int64_t>(Next(10)));
    ObserveAcks();
    // Restarts that are due.
    if (Status s = RestartDue(); !s) return s.error().message;
    if (op == kOps / 2) CorruptOneSlot();
    if (op == kOps / 3) GhostSendsOneChange();
    if (op == kOps / 4) cluster_->Start(kView, NodeRole::kObserver);
    const uint64_t what = Next(100);
    if (what >= 72 && what < 75) {
      // A sender whose writes time out for longer than the silence period (a DDS writer held
      // back by a killed reader blocked the server's loop for 2 s at a time). The server at any
      // moment, so a node may sign on and then lose it before it fetched its acknowledged
      // changes; a node or the standby only while everything else is well.
      const int64_t ms = 1000 + static_cast<int64_t>(Next(1500));  // silence_ms is 800
      if (Chance(0.5)) {
        if (cluster_->alive(kServer)) cluster_->net().BlockWrites(kServer, cluster_->now_ms() + ms);
      } else if (AllUp()) {
        std::vector<NodeAddress> others = nodes;
        if (with_standby_) others.push_back(kStandby);
        const NodeAddress who = others[Next(others.size())];
        cluster_->net().BlockWrites(who, cluster_->now_ms() + ms);
        blocked_until_ms_ = cluster_->now_ms() + ms;
      }
      if (trace_) {
        std::printf("t=%lld writes blocked for %lld ms\n",
                    static_cast<long long>(cluster_->now_ms()), static_cast<long long>(ms));
      }
    } else if (what < 75) {
      const NodeAddress who = nodes[Next(nodes.size())];
      if (cluster_->alive(who)) {
        if (auto f = Command(who); !f.empty()) return f;
      }
    } else if (what < 82) {
      // One crash at a time (the guarantee is about any single crash): a replica goes down only
      // when every other is up and signed on.
      const NodeAddress who = nodes[Next(nodes.size())];
      if (AllUp()) Crash(who);
    } else if (what < 86) {
      if (AllUp()) Crash(kServer);
    } else if (what < 88) {
      if (with_standby_ && AllUp()) Crash(kStandby);
    } else if (what < 90) {
      // Several processes at once, in any combination (issue 15: "restarts without state in
      // every combination"): each replica goes down with probability 1/2, at least two.
      if (AllUp()) {
        std::vector<NodeAddress> down;
        for (NodeAddress a : cluster_->live()) {
          if (a != kView && Chance(0.5)) down.push_back(a);
        }
        if (down.size() >= 2) {
          for (NodeAddress a : down) Crash(a);
        }
      }
    } else if (what < 92) {
      // Every process down but one node, which keeps creating; then it goes down too (issue
      // 15 item 2: its numbers were issued again after its restart).
      // The survivor is a freshly restarted incarnation, so it and its next incarnation learn
      // the same acknowledged maximum when they sign on: the case that reissued IDs.
      const NodeAddress who = nodes[Next(nodes.size())];
      if (AllUp()) {
        Crash(who);
        for (int64_t waited = 0; waited < 5000 && !(cluster_->alive(who) && AllUp());
             waited += 10) {
          cluster_->Run(10);
          ObserveAcks();
          if (Status s = RestartDue(); !s) return s.error().message;
        }
      }
      if (AllUp()) {
        for (NodeAddress a : cluster_->live()) {
          if (a != who && a != kView) Crash(a);
        }
        if (trace_) {
          std::printf("t=%lld all down but %s\n", static_cast<long long>(cluster_->now_ms()),
                      who.ToString().c_str());
        }
        const int commands = 1 + static_cast<int>(Next(4));
        for (int i = 0; i < commands; ++i) {
          cluster_->Run(10 + static_cast<int64_t>(Next(50)));
          if (auto f = Command(who); !f.empty()) return f;
        }
        Crash(who);
      }
    } else if (what < 95) {
      std::vector<NodeAddress> all = nodes;
      all.push_back(kServer);
      if (with_standby_) all.push_back(kStandby);
      std::vector<NodeAddress> a, b;
      for (NodeAddress n : all) (Chance(0.5) ? a : b).push_back(n);
      if (!partitioned_ && AllUp()) {
        cluster_->net().faults().Partition(a, b);
        partitioned_ = true;
      }
    } else {
      cluster_->net().faults().Heal();
      partitioned_ = false;
    }
  }
  // Heal: no more faults; everything crashed comes back.
  cluster_->net().faults().set_config({});
  cluster_->net().faults().Heal();
  for (NodeAddress a : cluster_->live()) cluster_->net().BlockWrites(a, 0);
  blocked_until_ms_ = 0;
  // Each comes back when its downtime is over, as during the run (a process restarts after its
  // last messages have landed).
  while (!restart_at_ms_.empty()) {
    cluster_->Run(10);
    ObserveAcks();
    if (Status s = RestartDue(); !s) return s.error().message;
  }
  // Every node creates once more after the last restarts, so a number reissued by a restarted
  // incarnation shows.
  for (int64_t waited = 0; waited < kHealMs; waited += 10) {
    bool all_signed_on = true;
    for (NodeAddress a : nodes) all_signed_on = all_signed_on && cluster_->at(a).signed_on();
    if (all_signed_on) break;
    cluster_->Run(10);
  }
  for (NodeAddress a : nodes) {
    Replica& r = cluster_->at(a);
    const int64_t before = r.own_change_seq();
    (void)r.Create(RandomParams(FeatureType::kCrater));
    RecordIssued(a, before);
    if (!failure_.empty()) return failure_;
  }
  cluster_->Run(kHealMs);
  ObserveAcks();
  if (std::string f = Check(); !f.empty()) return f;
  return CheckCorruptionRepaired();
}

void SimRun::GhostSendsOneChange() {
  // Its own draws (as the corruption's), so the rest of the schedule is drawn as without it.
  ghost_transport_ = cluster_->net().Join(kGhost, 1);
  PduBusConfig bc;
  bc.exercise_id = 1;
  bc.local = kGhost;
  bc.terrain_size_m = SimGround().size_m();
  bc.clock = [] { return 0u; };
  ghost_bus_ = std::make_unique<PduBus>(*ghost_transport_, bc);
  FeaturePdu f;
  const auto seq = static_cast<uint32_t>(2 + corrupt_rng_() % 3);  // 1..seq-1 never sent
  f.id = {kGhost.site, kGhost.host, seq};
  f.params = FeatureParams::Crater(40, 40, 3);
  f.change.changed_by = kGhost;
  f.change.change_seq = seq;
  f.change.lamport = 1 + corrupt_rng_() % 50;
  ghost_change_ = ChangeFrom(f, ChangeKind::kConstruct);
  if (auto sent = ghost_bus_->Publish(ToConstruct(f)); !sent) {
    std::fprintf(stderr, "gone author's change refused: %s\n", sent.error().message.c_str());
    std::abort();  // a valid PDU
  }
  if (trace_) {
    std::printf("t=%lld gone author %s sends change %u alone\n",
                static_cast<long long>(cluster_->now_ms()), kGhost.ToString().c_str(), seq);
  }
}

void SimRun::CorruptOneSlot() {
  // A slot the server holds durably, so its copy (the repair rule's winner) is the issued one.
  if (!cluster_->alive(kServer)) return;
  const auto durable = cluster_->at(kServer).durable_change_seq();
  std::vector<NodeAddress> replicas;
  for (NodeAddress a : cluster_->live()) {
    if (a != kServer && cluster_->at(a).signed_on()) replicas.push_back(a);
  }
  if (replicas.empty()) return;
  const NodeAddress victim = replicas[corrupt_rng_() % replicas.size()];
  Replica& r = cluster_->at(victim);
  std::vector<std::pair<NodeAddress, int64_t>> slots;  // (author, highest seq eligible)
  for (const auto& [author, d] : durable) {
    const ChangeLog* log = r.log(author);
    const int64_t top = log == nullptr ? 0 : std::min(log->contiguous(), d);
    if (top >= 1) slots.emplace_back(author, top);
  }
  if (slots.empty()) return;
  const auto [author, top] = slots[corrupt_rng_() % slots.size()];
  const int64_t seq = 1 + static_cast<int64_t>(corrupt_rng_() % static_cast<uint64_t>(top));
  Change bad = *r.log(author)->Find(seq);
  if (bad.kind == ChangeKind::kDestruct) {
    bad.stamp.lamport += 1;  // invisible in the terrain: only the logs' hashes show it
  } else {
    bad.params.length_m[0] += 0.5;  // crater radius, berm length or bridge span
  }
  if (!r.anti_entropy().Overwrite(bad).ok()) std::abort();  // the slot is held
  corruption_ = Corruption{victim, author, seq, crashes_[victim]};
  if (trace_) {
    std::printf("t=%lld corrupt %s's copy of %s:%lld\n", static_cast<long long>(cluster_->now_ms()),
                victim.ToString().c_str(), author.ToString().c_str(), static_cast<long long>(seq));
  }
}

std::string SimRun::CheckCorruptionRepaired() {
  if (!corruption_ || !cluster_->alive(corruption_->replica) ||
      crashes_[corruption_->replica] != corruption_->crashes) {
    return "";  // nothing corrupted, or the replica restarted since and holds no corruption
  }
  const Corruption& c = *corruption_;
  Replica& r = cluster_->at(c.replica);
  const Change* mine = r.log(c.author)->Find(c.seq);
  const ChangeLog* server_log = cluster_->at(kServer).log(c.author);
  const Change* theirs = server_log == nullptr ? nullptr : server_log->Find(c.seq);
  if (mine == nullptr || theirs == nullptr || !(*mine == *theirs)) {
    return fmt::format("{}'s corrupted copy of {}:{} was not repaired", c.replica.ToString(),
                       c.author.ToString(), c.seq);
  }
  if (r.anti_entropy().stats().slots_repaired == 0) {
    return fmt::format("{}'s corrupted copy of {}:{} is not counted as repaired",
                       c.replica.ToString(), c.author.ToString(), c.seq);
  }
  return "";
}

std::string SimRun::CheckObserver() {
  Replica& server = cluster_->at(kServer);
  Replica& view = cluster_->at(kView);
  if (view.diverged()) return "the observer is still diverged after healing";
  std::vector<NodeAddress> authors = cluster_->live();
  authors.push_back(kGhost);
  for (NodeAddress author : authors) {
    const ChangeLog* theirs = server.log(author);
    const ChangeLog* mine = view.log(author);
    if (theirs == nullptr) {
      observer_extra_ += mine == nullptr ? 0 : static_cast<int>(mine->size());
      continue;
    }
    for (const Change* c : theirs->Range(1, theirs->max_held())) {
      const Change* o = mine == nullptr ? nullptr : mine->Find(c->stamp.change_seq);
      if (o == nullptr || !(*o == *c)) {
        return fmt::format("the observer does not hold the server's change {}:{}",
                           author.ToString(), c->stamp.change_seq);
      }
    }
    if (mine != nullptr) {
      observer_extra_ += static_cast<int>(mine->size() - theirs->size());
    }
  }
  if (observer_extra_ == 0 && view.Digest() != server.Digest()) {
    return fmt::format("the observer holds the server's changes but its digest {} is not {}",
                       view.Digest(), server.Digest());
  }
  return "";
}

std::string SimRun::Check() {
  Replica& server = cluster_->at(kServer);
  const std::string digest = server.Digest();
  for (NodeAddress a : cluster_->live()) {
    if (a == kView) {
      if (std::string f = CheckObserver(); !f.empty()) return f;
      continue;
    }
    Replica& r = cluster_->at(a);
    if (r.diverged()) {
      const auto d = r.divergences().front();
      return fmt::format("{} is still diverged after healing: {}'s log with {}, changes {}..{}",
                         a.ToString(), d.author.ToString(), d.peer.ToString(), d.first_seq,
                         d.last_seq);
    }
    if (!r.caught_up()) {
      std::string logs;
      std::vector<NodeAddress> authors = cluster_->live();
      authors.push_back(kGhost);
      for (NodeAddress author : authors) {
        if (const ChangeLog* l = r.log(author)) {
          logs += fmt::format(" {}:[{} of {}", author.ToString(), l->contiguous(), l->max_known());
          for (const auto& [by, seq] : l->reports())
            logs += fmt::format(" {}says{}", by.ToString(), seq);
          for (const auto& [by, seq] : l->held_by())
            logs += fmt::format(" {}holds{}", by.ToString(), seq);
          if (l->max_held() > 0) logs += fmt::format(" held{}", l->max_held());
          logs += "]";
        }
      }
      if (trace_) {
        for (NodeAddress x : cluster_->live()) {
          if (const ChangeLog* g = cluster_->at(x).log(kGhost)) {
            std::printf("%s's log of the gone author: %lld of %lld, held %lld, gave_up %llu\n",
                        x.ToString().c_str(), static_cast<long long>(g->contiguous()),
                        static_cast<long long>(g->max_known()),
                        static_cast<long long>(g->max_held()),
                        static_cast<unsigned long long>(cluster_->at(x).counters().gave_up));
          }
        }
      }
      return fmt::format("{} is not caught up after healing:{}", a.ToString(), logs);
    }
    for (const auto& [author, n] : incarnation_) {
      const ChangeLog* mine = r.log(author);
      const ChangeLog* theirs = server.log(author);
      if (mine == nullptr || theirs == nullptr) continue;
      for (const Change* c : mine->Range(1, mine->max_held())) {
        const Change* o = theirs->Find(c->stamp.change_seq);
        if (o != nullptr && !(*o == *c)) {
          return fmt::format("{} and the server hold different changes {}:{} (a reused sequence)",
                             a.ToString(), author.ToString(), c->stamp.change_seq);
        }
      }
    }
    if (r.Digest() != digest && trace_) {
      for (const auto& [author, n] : incarnation_) {
        for (Replica* x : {&r, &server}) {
          std::string held;
          if (const ChangeLog* l = x->log(author)) {
            for (const Change* c : l->Range(1, l->max_held())) {
              held += fmt::format(" {}@{}:{}:{}", c->stamp.change_seq, c->stamp.lamport,
                                  static_cast<int>(c->kind), c->id.ToString());
            }
          }
          std::printf("  %s's log of %s:%s\n", x->config().address.ToString().c_str(),
                      author.ToString().c_str(), held.c_str());
        }
      }
    }
    if (r.Digest() != digest) {
      return fmt::format("{} digest {} != server digest {} ({} vs {} live features)", a.ToString(),
                         r.Digest(), digest, r.live_feature_count(), server.live_feature_count());
    }
  }
  // The oracle: what the server holds must be exactly the issued changes that survived, with
  // identical content, and materialise to the same terrain.
  RecordStore reference(SimGround());
  size_t present = 0;
  for (const Issued& i : issued_) {
    if (i.replaced) continue;
    const NodeAddress author = i.change.author();
    const ChangeLog* log = server.log(author);
    const Change* held = log != nullptr ? log->Find(i.change.stamp.change_seq) : nullptr;
    const bool acked = i.change.stamp.change_seq <= max_ack_[{author, i.incarnation}];
    const bool author_survived = incarnation_[author] == i.incarnation;
    if (held == nullptr) {
      if (acked) {
        return fmt::format("acknowledged change {}:{} was lost", author.ToString(),
                           i.change.stamp.change_seq);
      }
      if (author_survived) {
        return fmt::format("change {}:{} of a node that never crashed was lost", author.ToString(),
                           i.change.stamp.change_seq);
      }
      continue;
    }
    const bool held_void = held->kind == ChangeKind::kDestruct && issued_ids_.count(held->id) == 0;
    if (!(*held == i.change) && held_void && !acked && !author_survived) {
      continue;  // lost with its incarnation, and its sequence voided by the next one
    }
    if (!(*held == i.change)) {
      return fmt::format("change {}:{} is held with other content than issued", author.ToString(),
                         i.change.stamp.change_seq);
    }
    (void)reference.Apply(i.change);
    ++present;
  }
  // The gone author's log: its one change (unless every copy was dropped on the way) and the
  // voids that closed the gap before it, tombstones of numbers no one issued.
  const ChangeLog* ghost_log = ghost_change_ ? server.log(kGhost) : nullptr;
  if (const ChangeLog* log =
          ghost_log != nullptr && ghost_log->max_held() > 0 ? ghost_log : nullptr) {
    const int64_t seq = ghost_change_->stamp.change_seq;
    if (log->contiguous() != seq || log->max_held() != seq) {
      return fmt::format("the server holds the gone author's log up to {} of {}, not 1..{}",
                         log->contiguous(), log->max_held(), seq);
    }
    for (const Change* c : log->Range(1, seq - 1)) {
      if (c->kind != ChangeKind::kDestruct || issued_ids_.count(c->id) != 0 ||
          OriginOf(c->id) == kGhost) {
        return fmt::format("the gone author's change {} is not a void", c->stamp.change_seq);
      }
    }
    if (!(*log->Find(seq) == *ghost_change_)) return "the gone author's change is changed";
    if (trace_) {
      for (NodeAddress a : cluster_->live()) {
        std::printf("%s gave up on %llu changes\n", a.ToString().c_str(),
                    static_cast<unsigned long long>(cluster_->at(a).counters().gave_up));
      }
    }
    (void)reference.Apply(*ghost_change_);
  }
  // Everything else the server holds must be a void: a tombstone of a never-issued number.
  size_t held_total = 0, voids = 0;
  for (const auto& [a, n] : incarnation_) {
    const ChangeLog* log = server.log(a);
    if (log == nullptr) continue;
    held_total += log->size();
    for (const Change* c : log->Range(1, log->max_held())) {
      if (c->kind == ChangeKind::kDestruct && issued_ids_.count(c->id) == 0 &&
          OriginOf(c->id) == a) {
        ++voids;
      }
    }
  }
  if (held_total != present + voids) {
    return fmt::format("the server holds {} changes, {} of them issued and {} voids", held_total,
                       present, voids);
  }
  if (reference.live_count() != server.live_feature_count()) {
    return fmt::format("expected {} live features, the server has {}", reference.live_count(),
                       server.live_feature_count());
  }
  if (ComputeDigest(reference.terrain()).ToHex() != digest) {
    return "the server's terrain differs from the oracle's";
  }
  return "";
}

TEST(ProtocolSimTest, TheGuaranteeHoldsForEverySeed) {
  log::Init("sim", std::getenv("DT_SIM_LOG") != nullptr ? std::getenv("DT_SIM_LOG") : "error");
  const int64_t only = EnvInt("DT_SIM_SEED", 0);
  const int64_t first = only > 0 ? only : EnvInt("DT_SIM_FIRST_SEED", 1);
  const int64_t count = only > 0 ? 1 : EnvInt("DT_SIM_SEEDS", 1000);
  const auto dir = std::filesystem::temp_directory_path() /
                   fmt::format("dt_protocol_sim_{}", static_cast<long>(::getpid()));
  int failures = 0;
  int64_t sqlite_seeds = 0;
  int64_t simulated_ms = 0;
  int observer_extra_seeds = 0;
  const auto wall_start = std::chrono::steady_clock::now();
  for (int64_t seed = first; seed < first + count; ++seed) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    sqlite_seeds += seed % 10 == 3 ? 1 : 0;
    SimRun run(static_cast<uint64_t>(seed), dir);
    const std::string failure = run.Run();
    simulated_ms += run.simulated_ms();
    observer_extra_seeds += run.observer_extra() > 0 ? 1 : 0;
    if (!failure.empty()) {
      ++failures;
      ADD_FAILURE() << "seed " << seed << ": " << failure << "\n  reproduce: DT_SIM_SEED=" << seed
                    << " " << ::testing::UnitTest::GetInstance()->original_working_dir()
                    << "/protocol_sim_test";
      if (failures >= 10) break;
    }
  }
  const double wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start)
          .count();
  std::filesystem::remove_all(dir);
  RecordProperty("seeds", static_cast<int>(count));
  std::printf("%lld seeds from %lld (%lld with SQLite files): %d failed\n",
              static_cast<long long>(count), static_cast<long long>(first),
              static_cast<long long>(sqlite_seeds), failures);
  // A figure, not a check: how long runs of many seeds take (docs/performance.md).
  std::printf("%d seeds ended with the observer holding a lost change only it received\n",
              observer_extra_seeds);
  std::printf("simulated %.1f s in %.1f s wall (%.0fx real time), %.1f ms wall per seed\n",
              static_cast<double>(simulated_ms) / 1000.0, wall_ms / 1000.0,
              wall_ms > 0 ? static_cast<double>(simulated_ms) / wall_ms : 0.0,
              count > 0 ? wall_ms / static_cast<double>(count) : 0.0);
  std::printf("%lld earth moves issued by blade operations\n",
              static_cast<long long>(earth_moves_issued));
  // Blade work is in the schedules: a run of a few seeds issues some.
  if (count >= 10) {
    EXPECT_GT(earth_moves_issued, 0);
  }
}

}  // namespace
}  // namespace dt

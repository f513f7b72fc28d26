// The protocol simulation's schedule: replicas started, crashed and restarted, commands, faults,
// the steps "anti-entropy" and "gone author", then the heal (docs/protocol.md, "The proof").
#include <cstdio>

#include <fmt/format.h>

#include "simulation/protocol_sim.h"

#include "base/demand.h"
#include "pdu/conversion.h"
#include "server/sqlite_change_store.h"
#include "terrain/slump.h"

namespace dt::sim {

Status SimRun::StartServer(NodeAddress address, NodeRole role) {
  ChangeStore* store = nullptr;
  if (use_sqlite_) {
    // Reopened on every restart, as a restarted process would.
    stores_.erase(address);
    auto s = SqliteChangeStore::Open(dir_ / fmt::format("server-{}.db", address.host),
                                     SimGround().size_x_m(), SimGround().size_z_m());
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
  DT_UNREACHABLE();
}

int64_t earth_moves_issued = 0;

Status SimRun::BladeOp(Replica& r) {
  // A blade's work in miniature: soil cut from one post and piled on a neighbour, slumped to the
  // angle of repose on this replica's terrain, sent as earth moves.
  const HeightGrid& g = r.terrain().ground();
  const int i = 1 + static_cast<int>(Next(static_cast<uint64_t>(g.posts_x() - 2)));
  const int j = 1 + static_cast<int>(Next(static_cast<uint64_t>(g.posts_z() - 2)));
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
  bc.terrain_size_x_m = SimGround().size_x_m();
  bc.terrain_size_z_m = SimGround().size_z_m();
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
  auto sent = ghost_bus_->Publish(ToConstruct(f));
  if (!sent) {
    std::fprintf(stderr, "gone author's change refused: %s\n", sent.error().message.c_str());
  }
  DT_DEMAND(sent);  // a valid PDU
  if (trace_) {
    std::printf("t=%lld gone author %s sends change %u alone\n",
                static_cast<long long>(cluster_->now_ms()), kGhost.ToString().c_str(), seq);
  }
}

namespace {

// Changes a field the feature's kind uses, so the copy differs from the issued one in the terrain
// and in the record hash, and stays within the documented ranges.
void AlterUsedField(FeatureParams& p) {
  switch (p.type) {
    case FeatureType::kCrater:  // radius
    case FeatureType::kBerm:    // length
    case FeatureType::kBridge:  // span
    case FeatureType::kDitch:   // side run
      p.length_m[0] += 0.5;
      return;
    case FeatureType::kBermLine:  // crest height at the first point
      p.points.front().height_m += 0.5;
      return;
    case FeatureType::kArea:  // the water level, or the soil of a dry area
      if (p.material == Material::kWater) {
        p.height_m[0] += 0.5;
      } else {
        p.material = p.material == Material::kMud ? Material::kSand : Material::kMud;
      }
      return;
    case FeatureType::kEarthMove: {  // the first post's change, kept nonzero and in range
      int32_t& d = p.post_deltas.front().delta_mm;
      d = d >= kMaxPostDeltaMm ? d - 1 : (d == -1 ? 1 : d + 1);
      return;
    }
  }
  DT_UNREACHABLE();
}

}  // namespace

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
    AlterUsedField(bad.params);
    // Still a valid change, so a repair that re-sends this copy is refused by nothing but the
    // repair rule.
    DT_DEMAND(ValidateFeatureParams(bad.params).ok());
  }
  DT_DEMAND(r.anti_entropy().Overwrite(bad).ok());  // the slot is held
  corruption_ = Corruption{victim, author, seq, crashes_[victim]};
  if (trace_) {
    std::printf("t=%lld corrupt %s's copy of %s:%lld\n", static_cast<long long>(cluster_->now_ms()),
                victim.ToString().c_str(), author.ToString().c_str(), static_cast<long long>(seq));
  }
}

}  // namespace dt::sim

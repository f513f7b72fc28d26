// SimRun: one seeded schedule of the protocol simulation (simulation/test/protocol_sim_test.cc) and
// the checks of docs/protocol.md's guarantee after it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "engine/change_store.h"
#include "engine/id_reservation.h"
#include "engine/memory_change_store.h"
#include "simulation/sim_cluster.h"
#include "transport/pdu_bus.h"

namespace dt::sim {

using testing::SimCluster;

inline HeightGrid SimGround() { return HeightGrid(17, 8.0, 5.0f); }

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

// Earth moves the simulation's blade operations issued, over every seed run.
extern int64_t earth_moves_issued;

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
  // The observer's guarantee (docs/protocol.md "Observers"): the server's changes, identically,
  // and nothing else.
  std::string CheckObserver();
  // Changes the observer dropped: it alone held them (their author crashed before anyone else
  // got them).
  uint64_t observer_dropped_ = 0;

 public:
  uint64_t observer_dropped() const { return observer_dropped_; }

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

}  // namespace dt::sim

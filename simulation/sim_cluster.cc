#include "simulation/sim_cluster.h"

#include "base/demand.h"
#include "transport/retrying_transport.h"

namespace dt::testing {

SimCluster::SimCluster(uint64_t seed, HeightGrid ground, ReplicaConfig defaults, FaultConfig faults)
    : net_(seed, faults), ground_(std::move(ground)), defaults_(defaults) {}

SimCluster::~SimCluster() { members_.clear(); }

Replica& SimCluster::Start(NodeAddress address, NodeRole role, ChangeStore* store,
                           IdReservation* ids, const BaseGround* ground) {
  auto m = std::make_unique<Member>();
  // As in every process (runtime/process_runtime.cc): a refused write is queued and retried.
  m->transport = std::make_unique<RetryingTransport>(net_.Join(address, 1));
  PduBusConfig bc;
  bc.exercise_id = 1;
  bc.local = address;
  bc.terrain_size_x_m = ground_.size_x_m();
  bc.terrain_size_z_m = ground_.size_z_m();
  bc.terrain_posts_x = ground_.posts_x();
  bc.terrain_posts_z = ground_.posts_z();
  bc.clock = [] { return 0u; };  // relative time 0: deterministic
  m->bus = std::make_unique<PduBus>(*m->transport, bc);
  ReplicaConfig rc = defaults_;
  rc.address = address;
  rc.role = role;
  rc.store = store;
  rc.ids = ids;
  m->replica = ground != nullptr ? std::make_unique<Replica>(rc, *ground, *m->bus)
                                 : std::make_unique<Replica>(rc, ground_, *m->bus);
  m->replica->SignOn(net_.now_ms());
  Replica& r = *m->replica;
  members_[address] = std::move(m);
  return r;
}

void SimCluster::Crash(NodeAddress address) { members_.erase(address); }

void SimCluster::Run(int64_t ms, int64_t step_ms) {
  for (int64_t t = 0; t < ms; t += step_ms) {
    net_.AdvanceMs(step_ms);
    for (auto& [a, m] : members_) {
      auto r = m->bus->HandleTimeout(0);
      DT_DEMAND(r);  // SimNetwork never fails
    }
    for (auto& [a, m] : members_) m->replica->Tick(net_.now_ms());
  }
}

void SimCluster::Deliver(int64_t ms, int64_t step_ms) {
  for (int64_t t = 0; t < ms; t += step_ms) {
    net_.AdvanceMs(step_ms);
    for (auto& [a, m] : members_) {
      DT_DEMAND(m->bus->HandleTimeout(0));  // SimNetwork never fails
    }
  }
}

std::vector<NodeAddress> SimCluster::live() const {
  std::vector<NodeAddress> out;
  for (const auto& [a, m] : members_) out.push_back(a);
  return out;
}

}  // namespace dt::testing

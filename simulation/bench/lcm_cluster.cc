#include "simulation/bench/lcm_cluster.h"

#include <poll.h>

#include <array>
#include <chrono>
#include <cstdlib>

#include "engine/change.h"
#include "pdu/pdu_traits.h"

namespace dt::bench {
namespace {

size_t TypeIndex(PduType type) {
  for (size_t i = 0; i < kAllPduTypes.size(); ++i) {
    if (kAllPduTypes[i] == type) return i;
  }
  std::abort();  // every PduType is in kAllPduTypes
}

}  // namespace

int64_t SteadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

ReplicaConfig FastAckConfig() {
  ReplicaConfig rc;
  rc.max_feature_period_ms = 10;
  rc.silence_ms = 200;
  rc.playback_retry_ms = 100;
  rc.playback_window = 4096;
  return rc;
}

PduBusConfig BenchBusConfig(NodeAddress address, const HeightGrid& ground) {
  PduBusConfig bc;
  bc.exercise_id = kBenchExercise;
  bc.local = address;
  bc.terrain_size_x_m = ground.size_x_m();
  bc.terrain_size_z_m = ground.size_z_m();
  return bc;
}

Change BenchCraterConstruct(NodeAddress origin, int64_t n) {
  Change c;
  c.kind = ChangeKind::kConstruct;
  c.id = {origin.site, origin.host, static_cast<uint32_t>(n)};
  c.params = BenchCrater(n);
  c.stamp = {origin, static_cast<uint32_t>(n), static_cast<uint64_t>(n)};
  return c;
}

std::vector<uint8_t> BenchConstructBytes(NodeAddress origin) {
  return EncodePdu(ToConstruct(ToFeaturePdu(BenchCraterConstruct(origin, 1))));
}

// One LcmTransport("memq://"); each endpoint is a Transport whose handlers see every message.
class LcmCluster::MemqHub {
 public:
  class Endpoint final : public Transport {
   public:
    explicit Endpoint(MemqHub& hub) : hub_(hub) { hub_.endpoints_.push_back(this); }
    ~Endpoint() override { std::erase(hub_.endpoints_, this); }
    Status Publish(PduType type, std::span<const uint8_t> bytes) override {
      return hub_.lcm_.Publish(type, bytes);
    }
    void Subscribe(PduType type, Handler handler) override {
      handlers_[TypeIndex(type)].push_back(std::move(handler));
    }
    Result<int> HandleTimeout(int timeout_ms) override {
      return hub_.lcm_.HandleTimeout(timeout_ms);
    }
    int Fd() const override { return hub_.lcm_.Fd(); }
    std::string Url() const override { return "memq://"; }

    void Dispatch(size_t type_index, std::span<const uint8_t> bytes) {
      const int64_t t = SteadyNowNs();
      for (const Handler& h : handlers_[type_index]) h(bytes);
      busy_ns += SteadyNowNs() - t;
    }
    int64_t busy_ns = 0;

   private:
    MemqHub& hub_;
    std::array<std::vector<Handler>, kAllPduTypes.size()> handlers_;
  };

  MemqHub() : lcm_("memq://", kBenchExercise) {
    for (PduType t : kAllPduTypes) {
      lcm_.Subscribe(t, [this, t](std::span<const uint8_t> bytes) { Deliver(t, bytes); });
    }
  }

  LcmTransport& lcm() { return lcm_; }
  bool recording = false;
  std::vector<std::vector<uint8_t>> recorded;

 private:
  void Deliver(PduType type, std::span<const uint8_t> bytes) {
    if (recording && type == PduType::kConstruct) recorded.emplace_back(bytes.begin(), bytes.end());
    const size_t index = TypeIndex(type);
    // By index: a handler never adds or removes endpoints, but stay safe if one did.
    for (size_t i = 0; i < endpoints_.size(); ++i) endpoints_[i]->Dispatch(index, bytes);
  }

  LcmTransport lcm_;
  std::vector<Endpoint*> endpoints_;
};

LcmCluster::LcmCluster(std::string url, HeightGrid ground, ReplicaConfig defaults)
    : url_(std::move(url)),
      ground_(std::move(ground)),
      defaults_(defaults),
      start_ns_(SteadyNowNs()) {
  if (url_ == "memq://") hub_ = std::make_unique<MemqHub>();
}

LcmCluster::~LcmCluster() { members_.clear(); }

Replica& LcmCluster::Start(NodeAddress address, NodeRole role, ChangeStore* store) {
  return Start(address, role, store, defaults_);
}

Replica& LcmCluster::Start(NodeAddress address, NodeRole role, ChangeStore* store,
                           ReplicaConfig config) {
  auto m = std::make_unique<Member>();
  if (hub_) {
    m->transport = std::make_unique<MemqHub::Endpoint>(*hub_);
  } else {
    m->transport = MakeTransport(url_, kBenchExercise);
  }
  PduBusConfig bc = BenchBusConfig(address, ground_);
  bc.auth.key = key_;
  m->bus = std::make_unique<PduBus>(*m->transport, bc);
  config.address = address;
  config.role = role;
  config.store = store;
  m->replica = std::make_unique<Replica>(config, ground_, *m->bus);
  m->replica->SignOn(now_ms());
  Replica& r = *m->replica;
  members_[address] = std::move(m);
  return r;
}

void LcmCluster::Crash(NodeAddress address) { members_.erase(address); }

void LcmCluster::Pump(int wait_ms) {
  if (hub_) {
    if (!hub_->lcm().HandleTimeout(wait_ms)) std::abort();  // memq does not fail
  } else {
    std::vector<pollfd> fds;
    for (auto& [a, m] : members_) fds.push_back({m->transport->Fd(), POLLIN, 0});
    if (wait_ms > 0) (void)poll(fds.data(), fds.size(), wait_ms);
    for (auto& [a, m] : members_) (void)m->bus->HandleTimeout(0);
  }
  const int64_t now = now_ms();
  if (tick_period_ms_ > 0 && last_tick_ms_ >= 0 && now - last_tick_ms_ < tick_period_ms_) return;
  last_tick_ms_ = now;
  for (auto& [a, m] : members_) m->replica->Tick(now);
}

int64_t LcmCluster::ReceiveNs(NodeAddress address) const {
  auto* e = dynamic_cast<const MemqHub::Endpoint*>(members_.at(address)->transport.get());
  return e == nullptr ? 0 : e->busy_ns;
}

int64_t LcmCluster::now_ms() const { return (SteadyNowNs() - start_ns_) / 1000000; }

void LcmCluster::RecordConstructs(bool on) {
  if (hub_) hub_->recording = on;
}

std::vector<std::vector<uint8_t>> LcmCluster::TakeRecorded() {
  std::vector<std::vector<uint8_t>> out;
  if (hub_) out.swap(hub_->recorded);
  return out;
}

}  // namespace dt::bench

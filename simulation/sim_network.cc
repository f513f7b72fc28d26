#include "simulation/sim_network.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "base/demand.h"

namespace dt {

class SimNetwork::Endpoint final : public Transport {
 public:
  Endpoint(SimNetwork& net, NodeAddress node, uint8_t exercise_id)
      : net_(net), node_(node), exercise_id_(exercise_id) {
    fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (fd_ < 0) throw std::runtime_error("SimNetwork: eventfd failed");
  }
  ~Endpoint() override {
    net_.Leave(*this);
    close(fd_);
  }

  Status Publish(PduType type, std::span<const uint8_t> bytes) override {
    if (bytes.size() > kMaxPduBytes) {
      return Error{fmt::format("{} PDU of {} bytes exceeds the {}-byte single-datagram limit",
                               PduTypeName(type), bytes.size(), kMaxPduBytes)};
    }
    return net_.Publish(*this, type, bytes);
  }

  void Subscribe(PduType type, Handler handler) override {
    handlers_[type].push_back(std::move(handler));
  }

  Result<int> HandleTimeout(int /*timeout_ms*/) override {
    Drain();
    // Only what was due when the call began: a reply published by a handler waits for the next
    // call, as it would on a real network.
    const uint64_t order_limit = net_.next_order_;
    int n = 0;
    while (!inbox_.empty() && inbox_.top().due_ms <= net_.now_ms_ &&
           inbox_.top().order < order_limit) {
      Pending p = inbox_.top();
      inbox_.pop();
      ++net_.stats_.delivered;
      ++n;
      auto it = handlers_.find(p.type);
      if (it == handlers_.end()) continue;
      // Handlers may subscribe more handlers: iterate by index over a deque.
      for (size_t i = 0; i < it->second.size(); ++i) Call(it->second[i], *p.bytes);
    }
    Signal();
    return n;
  }

  int Fd() const override { return fd_; }
  std::string Url() const override {
    return fmt::format("sim://{}?exercise={}", node_.ToString(), exercise_id_);
  }

  void Enqueue(Pending p) {
    inbox_.push(std::move(p));
    Signal();
  }
  // Makes the fd readable iff something is due.
  void Signal() {
    Drain();
    if (!inbox_.empty() && inbox_.top().due_ms <= net_.now_ms_) {
      const uint64_t one = 1;
      [[maybe_unused]] ssize_t w = write(fd_, &one, sizeof one);
    }
  }

  NodeAddress node() const { return node_; }
  uint8_t exercise_id() const { return exercise_id_; }
  const Inbox& inbox() const { return inbox_; }

 private:
  static void Call(const Handler& h, const std::vector<uint8_t>& bytes) noexcept { h(bytes); }
  void Drain() {
    uint64_t v;
    [[maybe_unused]] ssize_t r = read(fd_, &v, sizeof v);
  }

  SimNetwork& net_;
  NodeAddress node_;
  uint8_t exercise_id_;
  int fd_ = -1;
  Inbox inbox_;
  std::map<PduType, std::deque<Handler>> handlers_;
};

SimNetwork::SimNetwork(uint64_t seed, FaultConfig faults) : faults_(faults, seed) {}

SimNetwork::~SimNetwork() {
  DT_DEMAND(endpoints_.empty());  // endpoints hold references into the network
}

std::unique_ptr<Transport> SimNetwork::Join(NodeAddress node, uint8_t exercise_id) {
  for (const Endpoint* e : endpoints_) {
    if (e->node() == node && e->exercise_id() == exercise_id) {
      throw std::invalid_argument(fmt::format("SimNetwork: node {} already joined exercise {}",
                                              node.ToString(), exercise_id));
    }
  }
  auto endpoint = std::make_unique<Endpoint>(*this, node, exercise_id);
  endpoints_.push_back(endpoint.get());
  return endpoint;
}

void SimNetwork::Leave(Endpoint& endpoint) {
  endpoints_.erase(std::remove(endpoints_.begin(), endpoints_.end(), &endpoint), endpoints_.end());
}

void SimNetwork::BlockWrites(NodeAddress node, int64_t until_ms) {
  if (until_ms <= now_ms_) {
    writes_blocked_until_ms_.erase(node);
  } else {
    writes_blocked_until_ms_[node] = until_ms;
  }
}

bool SimNetwork::WritesBlocked(NodeAddress node) const {
  auto it = writes_blocked_until_ms_.find(node);
  return it != writes_blocked_until_ms_.end() && now_ms_ < it->second;
}

Status SimNetwork::Publish(Endpoint& from, PduType type, std::span<const uint8_t> bytes) {
  if (WritesBlocked(from.node())) {
    ++stats_.write_failures;
    return Error{fmt::format("SimNetwork: write by {} on {} timed out (writes blocked until {} ms)",
                             from.node().ToString(), ChannelName(from.exercise_id(), type),
                             writes_blocked_until_ms_.at(from.node()))};
  }
  ++stats_.published;
  auto shared = std::make_shared<const std::vector<uint8_t>>(bytes.begin(), bytes.end());
  for (Endpoint* to : endpoints_) {
    if (to->exercise_id() != from.exercise_id()) continue;
    const std::vector<int64_t> delays = faults_.Fate(from.node(), to->node());
    if (delays.empty()) ++stats_.dropped;
    for (int64_t d : delays) {
      ++stats_.copies_queued;
      to->Enqueue(Pending{now_ms_ + d, next_order_++, type, shared});
    }
  }
  return Status::Ok();
}

void SimNetwork::AdvanceMs(int64_t ms) {
  if (ms < 0) throw std::invalid_argument(fmt::format("SimNetwork: AdvanceMs({}) < 0", ms));
  now_ms_ += ms;
  for (Endpoint* e : endpoints_) e->Signal();
}

int64_t SimNetwork::NextDeliveryMs() const {
  int64_t next = -1;
  for (const Endpoint* e : endpoints_) {
    if (!e->inbox().empty() && (next < 0 || e->inbox().top().due_ms < next)) {
      next = e->inbox().top().due_ms;
    }
  }
  return next;
}

size_t SimNetwork::in_flight() const {
  size_t n = 0;
  for (const Endpoint* e : endpoints_) n += e->inbox().size();
  return n;
}

}  // namespace dt

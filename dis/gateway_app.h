// GatewayApp: the DIS gateway process (docs/dis.md "The gateway"): an observer process of the
// exercise (a node member when it imports craters) with its VehicleState subscription, the DIS
// socket and the translation between them.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dis/gateway_core.h"
#include "dis/udp_endpoint.h"
#include "runtime/exercise_config.h"
#include "runtime/observer_process.h"

namespace dt::dis {

class GatewayApp : public ObserverProcess {
 public:
  // Throws std::invalid_argument when the exercise has no [dis] named `name` (or a bad origin),
  // std::runtime_error when the DIS socket cannot be made.
  GatewayApp(const ExerciseConfig& exercise, const std::string& name);
  ~GatewayApp() override;

  const GatewayCore& core() const { return *core_; }
  const DisConfig& config() const { return dis_; }

 private:
  // The protocol's tick is done: the DIS input, then the vehicles' heartbeats and the features'
  // Object States.
  void OnTick(int64_t now_ms) override;
  void AddPollFds(std::vector<pollfd>& fds) const override;
  void OnWoken(int64_t now_ms) override;
  // vehicles: the exercise's vehicles it sends to DIS and the outside entities it imported.
  std::optional<ControlReply> HandleOwn(const ControlCommand& command) override;
  std::string StatusLines() const override { return core_->StatusLines(); }
  std::string RefusalText() const override;
  std::string StopSummary() const override;
  void DrainDis(int64_t now_ms);

  const DisConfig& dis_;
  std::unique_ptr<UdpEndpoint> socket_;
  std::unique_ptr<GatewayCore> core_;
  bool tracking_ = false;  // the replica reports touched records; all were sent once
};

}  // namespace dt::dis

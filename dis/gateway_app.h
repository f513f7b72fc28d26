// GatewayApp: the DIS gateway process (docs/dis.md "The gateway"): a replica of the exercise
// (an observer, or a node when it imports craters), its VehicleState subscription, the DIS
// socket and the translation between them, stepped by dt_dis's loop.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "dis/gateway_core.h"
#include "dis/udp_endpoint.h"
#include "engine/replica.h"
#include "runtime/control_protocol.h"
#include "runtime/control_server.h"
#include "runtime/exercise_config.h"
#include "runtime/id_reservation_file.h"
#include "runtime/process_runtime.h"

namespace dt::dis {

class GatewayApp {
 public:
  // Throws std::invalid_argument when the exercise has no [dis] named `name` (or a bad origin),
  // std::runtime_error when the DIS socket cannot be made.
  GatewayApp(const ExerciseConfig& exercise, const std::string& name);
  ~GatewayApp();

  void Start(int64_t now_ms);
  // Protocol tick, then the vehicles' heartbeats and the features' Object States.
  void Tick(int64_t now_ms);
  ControlReply Handle(std::string_view line);
  // Waits up to timeout_ms for the bus, the DIS socket or the control socket, then handles
  // what the bus and the DIS socket have.
  void Wait(const ControlServer& control, int timeout_ms);

  bool quit_requested() const { return quit_; }
  const Replica& replica() const { return *replica_; }
  const GatewayCore& core() const { return *core_; }
  const DisConfig& config() const { return dis_; }
  NodeRole role() const { return role_; }

 private:
  void DrainDis(int64_t now_ms);

  const ExerciseConfig& exercise_;
  const DisConfig& dis_;
  NodeRole role_;
  ProcessTransport transport_;
  std::unique_ptr<IdReservationFile> ids_;
  std::unique_ptr<Replica> replica_;
  std::unique_ptr<UdpEndpoint> socket_;
  std::unique_ptr<GatewayCore> core_;
  int64_t now_ms_ = 0;
  bool quit_ = false;
};

}  // namespace dt::dis

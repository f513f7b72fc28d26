// LcmTransport: the Transport over LCM (udpm multicast, or memq in one process).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "transport/transport.h"

struct _lcm_t;

namespace dt {

// Wraps one lcm_t. Avoids LCM 1.3.1's traps: every subscription queue is unlimited (the
// default of 30 drops most of a burst), a udpm URL gets recv_buf_size=2097152 unless it sets
// one (with a warning when net.core.rmem_max grants less), messages over kMaxPduBytes are
// refused so each PDU is one datagram, and all handling happens in HandleTimeout.
class LcmTransport final : public Transport {
 public:
  // url: "memq://" or "udpm://..."; throws std::runtime_error if LCM cannot be created.
  LcmTransport(std::string url, uint8_t exercise_id);
  ~LcmTransport() override;
  LcmTransport(const LcmTransport&) = delete;
  LcmTransport& operator=(const LcmTransport&) = delete;

  Status Publish(PduType type, std::span<const uint8_t> bytes) override;
  void Subscribe(PduType type, Handler handler) override;
  Result<int> HandleTimeout(int timeout_ms) override;
  int Fd() const override;
  std::string Url() const override { return url_; }

  // The URL given to LCM (with the receive buffer added).
  const std::string& lcm_url() const { return lcm_url_; }

 private:
  struct Subscription;
  static void Dispatch(const void* rbuf, const char* channel, void* user) noexcept;

  std::string url_;
  std::string lcm_url_;
  uint8_t exercise_id_;
  _lcm_t* lcm_ = nullptr;
  std::array<std::string, kAllPduTypes.size()> channels_;
  std::vector<std::unique_ptr<Subscription>> subscriptions_;
  int dispatched_ = 0;
};

// The receive buffer LcmTransport asks for on udpm (bytes).
inline constexpr int kLcmRecvBufBytes = 2097152;

}  // namespace dt

#include "transport/lcm_transport.h"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>
#include <lcm/lcm.h>

#include "base/demand.h"
#include "log/log.h"

namespace dt {
namespace {

size_t IndexOf(PduType type) {
  for (size_t i = 0; i < kAllPduTypes.size(); ++i) {
    if (kAllPduTypes[i] == type) return i;
  }
  DT_UNREACHABLE();  // PduType values are all in kAllPduTypes
}

// Adds recv_buf_size to a udpm URL that sets none, and warns when the kernel caps it lower:
// LCM 1.3.1 accepts the smaller buffer silently, and a burst then overflows it.
std::string WithReceiveBuffer(const std::string& url) {
  if (url.rfind("udpm://", 0) != 0) return url;
  std::string out = url;
  if (out.find("recv_buf_size=") == std::string::npos) {
    out += (out.find('?') == std::string::npos ? "?" : "&");
    out += fmt::format("recv_buf_size={}", kLcmRecvBufBytes);
  }
  std::ifstream rmem("/proc/sys/net/core/rmem_max");
  long rmem_max = 0;
  if (rmem >> rmem_max && rmem_max < kLcmRecvBufBytes) {
    DT_LOG_WARN(
        "udpm: the kernel grants at most {} receive-buffer bytes (net.core.rmem_max), less than "
        "the {} asked for; bursts may be dropped. Raise it: sysctl -w net.core.rmem_max={}",
        rmem_max, kLcmRecvBufBytes, kLcmRecvBufBytes);
  }
  return out;
}

}  // namespace

struct LcmTransport::Subscription {
  LcmTransport* owner = nullptr;
  Handler handler;
  lcm_subscription_t* lcm_sub = nullptr;
};

LcmTransport::LcmTransport(std::string url, uint8_t exercise_id)
    : url_(std::move(url)), lcm_url_(WithReceiveBuffer(url_)), exercise_id_(exercise_id) {
  lcm_ = lcm_create(lcm_url_.c_str());
  if (lcm_ == nullptr) {
    throw std::runtime_error(fmt::format("cannot create LCM for '{}'", lcm_url_));
  }
  for (size_t i = 0; i < kAllPduTypes.size(); ++i) {
    channels_[i] = ChannelName(exercise_id_, kAllPduTypes[i]);
  }
}

LcmTransport::~LcmTransport() {
  for (auto& s : subscriptions_) lcm_unsubscribe(lcm_, s->lcm_sub);
  lcm_destroy(lcm_);
}

Status LcmTransport::Publish(PduType type, std::span<const uint8_t> bytes) {
  if (bytes.size() > kMaxPduBytes) {
    return Error{fmt::format("{} PDU of {} bytes exceeds the {}-byte single-datagram limit",
                             PduTypeName(type), bytes.size(), kMaxPduBytes)};
  }
  const std::string& channel = channels_[IndexOf(type)];
  if (lcm_publish(lcm_, channel.c_str(), bytes.data(), static_cast<unsigned>(bytes.size())) != 0) {
    return Error{fmt::format("LCM publish on {} via '{}' failed", channel, url_)};
  }
  return Status::Ok();
}

void LcmTransport::Subscribe(PduType type, Handler handler) {
  auto sub = std::make_unique<Subscription>();
  sub->owner = this;
  sub->handler = std::move(handler);
  // LCM channel arguments are regular expressions; our names hold only [A-Z0-9_].
  sub->lcm_sub = lcm_subscribe(
      lcm_, channels_[IndexOf(type)].c_str(),
      [](const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
        LcmTransport::Dispatch(rbuf, channel, user);
      },
      sub.get());
  if (sub->lcm_sub == nullptr) {
    throw std::runtime_error(
        fmt::format("LCM refused a subscription to {}", channels_[IndexOf(type)]));
  }
  // 0 = unlimited: the default of 30 drops most of a burst.
  lcm_subscription_set_queue_capacity(sub->lcm_sub, 0);
  subscriptions_.push_back(std::move(sub));
}

void LcmTransport::Dispatch(const void* rbuf_void, const char* /*channel*/, void* user) noexcept {
  const auto* rbuf = static_cast<const lcm_recv_buf_t*>(rbuf_void);
  auto* sub = static_cast<Subscription*>(user);
  sub->owner->dispatched_++;
  sub->handler(std::span<const uint8_t>(static_cast<const uint8_t*>(rbuf->data), rbuf->data_size));
}

Result<int> LcmTransport::HandleTimeout(int timeout_ms) {
  dispatched_ = 0;
  // lcm_handle_timeout dispatches one message per call: wait for the first, then drain what is
  // already queued, bounded so a flood cannot starve the caller's loop.
  int rc = lcm_handle_timeout(lcm_, timeout_ms);
  for (int i = 0; rc > 0 && i < 100000; ++i) rc = lcm_handle_timeout(lcm_, 0);
  if (rc < 0) return Error{fmt::format("LCM handle on '{}' failed", url_)};
  return dispatched_;
}

int LcmTransport::Fd() const { return lcm_get_fileno(lcm_); }

}  // namespace dt

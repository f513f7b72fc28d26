// RawLcmLink: raw LCM publish and receive of pre-encoded messages, the baseline that the PDU and
// protocol benchmarks divide by.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <lcm/lcm.h>

namespace dt::bench {

// One lcm_t publishes and a counting handler receives on one channel: for memq the same lcm_t
// (memq is this object only), otherwise a second one with the receive buffer LcmTransport asks
// for. No PduBus, no decoding: what LCM itself costs per message.
class RawLcmLink {
 public:
  RawLcmLink(const std::string& url, std::string channel) : channel_(std::move(channel)) {
    std::string lcm_url = url;
    if (url != "memq://") lcm_url += "&recv_buf_size=2097152";
    tx_ = lcm_create(lcm_url.c_str());
    rx_ = url == "memq://" ? tx_ : lcm_create(lcm_url.c_str());
    sub_ = lcm_subscribe(
        rx_, channel_.c_str(),
        [](const lcm_recv_buf_t*, const char*, void* user) { ++*static_cast<int64_t*>(user); },
        &received_);
    lcm_subscription_set_queue_capacity(sub_, 0);  // unlimited, as LcmTransport sets it
  }
  ~RawLcmLink() {
    lcm_unsubscribe(rx_, sub_);
    if (rx_ != tx_) lcm_destroy(rx_);
    lcm_destroy(tx_);
  }
  RawLcmLink(const RawLcmLink&) = delete;
  RawLcmLink& operator=(const RawLcmLink&) = delete;

  // Publishes `count` copies of `bytes`, then handles until they all arrived or 2 s passed (a
  // lost datagram must not hang the run). Returns the number lost.
  int64_t Send(std::span<const uint8_t> bytes, int count) {
    const int64_t target = received_ + count;
    for (int i = 0; i < count; ++i) Publish(bytes);
    return ReceiveUntil(target);
  }

  // Publishes every message in batches of `batch`, handling each batch as above. Returns the
  // number lost.
  int64_t Transfer(std::span<const std::vector<uint8_t>> messages, size_t batch) {
    int64_t lost = 0;
    for (size_t i = 0; i < messages.size(); i += batch) {
      const size_t end = std::min(messages.size(), i + batch);
      const int64_t target = received_ + static_cast<int64_t>(end - i);
      for (size_t j = i; j < end; ++j) Publish(messages[j]);
      lost += ReceiveUntil(target);
    }
    return lost;
  }

 private:
  void Publish(std::span<const uint8_t> bytes) {
    lcm_publish(tx_, channel_.c_str(), bytes.data(), static_cast<unsigned>(bytes.size()));
  }

  int64_t ReceiveUntil(int64_t target) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (received_ < target) {
      if (std::chrono::steady_clock::now() > deadline) {
        const int64_t lost = target - received_;
        received_ = target;
        return lost;
      }
      int r = lcm_handle_timeout(rx_, 10);
      while (r > 0) r = lcm_handle_timeout(rx_, 0);
    }
    return 0;
  }

  std::string channel_;
  lcm_t* tx_ = nullptr;
  lcm_t* rx_ = nullptr;
  lcm_subscription_t* sub_ = nullptr;
  int64_t received_ = 0;
};

}  // namespace dt::bench

// RawLcmLink: raw LCM publish and receive of pre-encoded messages, the baseline that the PDU and
// protocol benchmarks divide by.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
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

// The same over udpm with each receiver on its own thread and its own socket, as in separate
// processes: the baseline for replicas that run side by side (simulation/bench/replica_thread.h).
// `receivers` sockets join the group; a message counts as transferred once every one holds it,
// so 3 receivers put on the kernel and the cores the deliveries an exercise of a sender, one
// other node and a server has (the sender's own copy, the node's and the server's).
class ThreadedRawLcmLink {
 public:
  ThreadedRawLcmLink(const std::string& udpm_url, std::string channel, int receivers = 1)
      : channel_(std::move(channel)) {
    if (receivers < 1) {
      throw std::invalid_argument("ThreadedRawLcmLink needs at least one receiver, got " +
                                  std::to_string(receivers));
    }
    const std::string lcm_url = udpm_url + "&recv_buf_size=2097152";
    tx_ = lcm_create(lcm_url.c_str());
    receivers_.resize(static_cast<size_t>(receivers));
    for (Receiver& r : receivers_) {
      r.link = this;
      r.lcm = lcm_create(lcm_url.c_str());
      r.sub = lcm_subscribe(
          r.lcm, channel_.c_str(),
          [](const lcm_recv_buf_t*, const char*, void* user) {
            auto* self = static_cast<Receiver*>(user);
            {
              std::lock_guard lock(self->link->mutex_);
              ++self->received;
            }
            self->link->arrived_.notify_one();
          },
          &r);
      lcm_subscription_set_queue_capacity(r.sub, 0);
    }
    for (Receiver& r : receivers_) {
      r.thread = std::thread([this, &r] {
        while (!stop_) (void)lcm_handle_timeout(r.lcm, 1);
      });
    }
  }
  ~ThreadedRawLcmLink() {
    stop_ = true;
    for (Receiver& r : receivers_) {
      r.thread.join();
      lcm_unsubscribe(r.lcm, r.sub);
      lcm_destroy(r.lcm);
    }
    lcm_destroy(tx_);
  }
  ThreadedRawLcmLink(const ThreadedRawLcmLink&) = delete;
  ThreadedRawLcmLink& operator=(const ThreadedRawLcmLink&) = delete;

  // Publishes every message in batches of `batch`, each batch once every receiver holds the one
  // before (a window, so nothing overflows a socket), then waits for the last. Returns the
  // messages some receiver lost (a batch waits at most 2 s).
  int64_t Transfer(std::span<const std::vector<uint8_t>> messages, size_t batch) {
    int64_t lost = 0;
    for (size_t i = 0; i < messages.size(); i += batch) {
      const size_t end = std::min(messages.size(), i + batch);
      int64_t target = 0;
      {
        std::lock_guard lock(mutex_);
        target = SlowestLocked() + static_cast<int64_t>(end - i);
      }
      for (size_t j = i; j < end; ++j) {
        lcm_publish(tx_, channel_.c_str(), messages[j].data(),
                    static_cast<unsigned>(messages[j].size()));
      }
      std::unique_lock lock(mutex_);
      if (!arrived_.wait_for(lock, std::chrono::seconds(2),
                             [&] { return SlowestLocked() >= target; })) {
        lost += target - SlowestLocked();
        for (Receiver& r : receivers_) r.received = std::max(r.received, target);
      }
    }
    return lost;
  }

 private:
  struct Receiver {
    ThreadedRawLcmLink* link = nullptr;
    lcm_t* lcm = nullptr;
    lcm_subscription_t* sub = nullptr;
    int64_t received = 0;  // guarded by link->mutex_
    std::thread thread;
  };
  int64_t SlowestLocked() const {
    int64_t slowest = receivers_.front().received;
    for (const Receiver& r : receivers_) slowest = std::min(slowest, r.received);
    return slowest;
  }

  std::string channel_;
  lcm_t* tx_ = nullptr;
  std::vector<Receiver> receivers_;  // sized once: the threads hold references
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::atomic<bool> stop_{false};
};

}  // namespace dt::bench

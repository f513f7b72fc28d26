// LoopRequests: questions from the web server's threads answered on the view's loop, which alone
// may read the replica's terrain.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace dt {

class LoopRequests {
 public:
  // At most this many questions wait at once; more are turned away at once (a busy loop should
  // not gather a queue of pages' requests).
  static constexpr size_t kMaxWaiting = 8;

  // On a web server thread: waits for the loop's answer, up to timeout_ms; nullopt when it did
  // not come in time or too many are waiting.
  std::optional<std::string> Ask(std::string question, int timeout_ms);
  // On the loop: answers up to `max` waiting questions with answer(question).
  void Serve(const std::function<std::string(const std::string&)>& answer, size_t max);
  size_t waiting() const;

 private:
  struct Pending {
    std::string question;
    std::promise<std::string> answer;
  };
  mutable std::mutex mu_;
  std::deque<std::shared_ptr<Pending>> queue_;
};

}  // namespace dt

#include "view/loop_requests.h"

#include <chrono>
#include <vector>

namespace dt {

std::optional<std::string> LoopRequests::Ask(std::string question, int timeout_ms) {
  auto p = std::make_shared<Pending>();
  p->question = std::move(question);
  std::future<std::string> f = p->answer.get_future();
  {
    std::lock_guard lock(mu_);
    if (queue_.size() >= kMaxWaiting) return std::nullopt;
    queue_.push_back(p);
  }
  if (f.wait_for(std::chrono::milliseconds(timeout_ms)) != std::future_status::ready) {
    // Left in the queue if not yet taken: the loop answers it into a promise nobody reads.
    std::lock_guard lock(mu_);
    std::erase(queue_, p);
    return std::nullopt;
  }
  return f.get();
}

void LoopRequests::Serve(const std::function<std::string(const std::string&)>& answer, size_t max) {
  std::vector<std::shared_ptr<Pending>> taken;
  {
    std::lock_guard lock(mu_);
    while (!queue_.empty() && taken.size() < max) {
      taken.push_back(std::move(queue_.front()));
      queue_.pop_front();
    }
  }
  for (auto& p : taken) p->answer.set_value(answer(p->question));
}

size_t LoopRequests::waiting() const {
  std::lock_guard lock(mu_);
  return queue_.size();
}

}  // namespace dt

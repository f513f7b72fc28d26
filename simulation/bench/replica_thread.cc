#include "simulation/bench/replica_thread.h"

#include <poll.h>
#include <pthread.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cstdlib>
#include <list>
#include <utility>
#include <vector>

#include "transport/transport.h"

namespace dt::bench {
ReplicaThread::ReplicaThread(const std::string& url, HeightGrid ground, ReplicaConfig config,
                             ChangeStore* store, int64_t epoch_ns,
                             std::shared_ptr<const ExerciseKey> key, bool batch)
    : epoch_ns_(epoch_ns) {
  transport_ = MakeTransport(url, kBenchExercise);
  PduBusConfig bc = BenchBusConfig(config.address, ground);
  bc.auth.key = std::move(key);
  bc.batch = batch;
  bus_ = std::make_unique<PduBus>(*transport_, bc);
  config.store = store;
  replica_ = std::make_unique<Replica>(config, std::move(ground), *bus_);
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) std::abort();  // out of file descriptors: nothing to measure
  replica_->SignOn(NowMs());
  thread_ = std::thread([this] { Loop(); });
  // Named for profiles (perf report --sort comm): "replica-1:100" (at most 15 characters).
  const std::string name = "replica-" + config.address.ToString();
  (void)pthread_setname_np(thread_.native_handle(), name.substr(0, 15).c_str());
}

ReplicaThread::~ReplicaThread() {
  stop_ = true;
  const uint64_t one = 1;
  (void)write(wake_fd_, &one, sizeof one);
  thread_.join();
  replica_.reset();
  bus_.reset();
  transport_.reset();
  close(wake_fd_);
}

std::future<int64_t> ReplicaThread::Post(Step step) {
  Pending p{std::move(step), {}};
  auto future = p.done.get_future();
  {
    std::lock_guard lock(mutex_);
    incoming_.push_back(std::move(p));
  }
  const uint64_t one = 1;
  (void)write(wake_fd_, &one, sizeof one);
  return future;
}

void ReplicaThread::Run(const std::function<void(Replica&)>& fn) {
  Post([&fn](Replica& r) {
    fn(r);
    return true;
  }).wait();
}

void ReplicaThread::Loop() {
  std::list<Pending> steps;  // this thread's only
  bool busy = false;         // the last round dispatched something
  while (!stop_) {
    // While traffic flows, no wait: straight back to the socket. Otherwise wait for traffic or a
    // new step; a waiting step (creations held by a full window, a check for progress) waits
    // for traffic too, so it never spins.
    if (!busy) {
      pollfd fds[2] = {{transport_->Fd(), POLLIN, 0}, {wake_fd_, POLLIN, 0}};
      (void)poll(fds, 2, 1);
      if ((fds[1].revents & POLLIN) != 0) {
        uint64_t count = 0;
        (void)read(wake_fd_, &count, sizeof count);
      }
    }
    // One round is a process's tick: what it publishes leaves packed at its end (PduBus::Batch).
    // A finished step is dated when it finished but reported only once the tick's PDUs are out:
    // waking the waiting thread first let it take a core before a lone change had left, which
    // unbatched sends never waited for.
    std::vector<std::pair<std::promise<int64_t>, int64_t>> finished;
    Result<int> dispatched = 0;
    {
      PduBus::Batch tick(*bus_);
      dispatched = bus_->HandleTimeout(0);
      replica_->Tick(NowMs());
      {
        std::lock_guard lock(mutex_);
        for (Pending& p : incoming_) steps.push_back(std::move(p));
        incoming_.clear();
      }
      for (auto it = steps.begin(); it != steps.end();) {
        if (it->step(*replica_)) {
          finished.emplace_back(std::move(it->done), SteadyNowNs());
          it = steps.erase(it);
        } else {
          ++it;
        }
      }
    }
    for (auto& [done, at_ns] : finished) done.set_value(at_ns);
    busy = dispatched && dispatched.value() > 0;
  }
}

uint64_t ReplicaThread::BatchesSent() {
  uint64_t sent = 0;
  Run([&](Replica&) { sent = bus_->batches_sent(); });
  return sent;
}

int64_t ReplicaThread::CpuNs() {
  clockid_t clock{};
  timespec t{};
  if (pthread_getcpuclockid(thread_.native_handle(), &clock) != 0 ||
      clock_gettime(clock, &t) != 0) {
    return -1;
  }
  return int64_t{t.tv_sec} * 1000000000 + t.tv_nsec;
}

}  // namespace dt::bench

// pdu_exchange_peer: the second process of the two-process PDU exchange test.
// Usage: pdu_exchange_peer <transport-url> <count> <ready-fd> <time-limit-s>
// Writes "ready\n" to ready-fd once subscribed, runs the exchange, prints the result line on
// stdout and exits 0 if it finished.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "log/log.h"
#include "tests/pdu/exchange.h"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s <url> <count> <ready-fd> <time-limit-s>\n", argv[0]);
    return 2;
  }
  dt::log::Init("exchange-peer", "warn");
  const std::string url = argv[1];
  const long count = std::strtol(argv[2], nullptr, 10);
  const int ready_fd = static_cast<int>(std::strtol(argv[3], nullptr, 10));
  const long limit_s = std::strtol(argv[4], nullptr, 10);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(limit_s);
  auto transport = dt::MakeTransport(url, dt::exchange::kExercise);
  const auto result = dt::exchange::Run(*transport, dt::exchange::kPeer, count, deadline, [&] {
    const char ready[] = "ready\n";
    if (write(ready_fd, ready, sizeof ready - 1) != sizeof ready - 1) std::exit(3);
    close(ready_fd);
    if (!dt::exchange::AwaitPeerReaders(*transport, static_cast<int>(limit_s) * 1000)) {
      std::fprintf(stderr, "peer: the driver's readers never matched\n");
    }
  });
  std::printf("%s\n", result.ToLine().c_str());
  std::fflush(stdout);
  return result.finished ? 0 : 1;
}

// BenchPeer: one process of the hosts benchmark (a replica, or a raw sender or receiver) on its
// own host, driven line by line over its stdin and stdout by hosts_bench.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/feature_id.h"

namespace dt::hostsbench {

enum class PeerKind { kServer, kNode, kRawSend, kRawRecv };

struct PeerOptions {
  PeerKind kind = PeerKind::kNode;
  std::string url;  // the carrier's URL on this host
  NodeAddress address;
  bool fast_ack = false;            // bench::FastAckConfig (throughput) or the protocol defaults
  double drop_probability = 0.0;    // the fault-injecting transport's loss on receipt
  int64_t other_site_delay_ms = 0;  // added on receipt to copies from another site
  int playback_window_max = 0;      // ReplicaConfig's; 0: the protocol default
};

// The peer's command line after `hosts_bench --peer`, and back.
std::vector<std::string> PeerArgs(const PeerOptions& o);
// Throws std::invalid_argument naming the argument for a malformed line.
PeerOptions ParsePeerArgs(const std::vector<std::string>& args);

// The raw peers' messages: Construct-sized bytes from these origins, so the fault-injecting
// transport sees a sender on the right site.
inline constexpr NodeAddress kRawDataOrigin{1, 201};  // the measured messages (site 1)
inline constexpr NodeAddress kRawAckOrigin{2, 202};   // a receiver's acknowledgement (site 2)
inline constexpr NodeAddress kRawPingOrigin{1, 203};  // the sender's hello before the transfer
inline constexpr NodeAddress kRawPongOrigin{2, 204};  // the receiver's answer to it

// Runs the peer until stdin ends or `quit`. Prints `0 ok <ns>` once its transport is up (a
// replica: when it has called SignOn, the start of a rejoin), then answers each command line `<id>
// <verb> [args]` with `<id> ok <ns> [values]` (or `<id> error <text>`) when it is done; <ns> is the
// steady clock, which every host of one machine shares. Returns the exit code. Verbs: a replica's
// ping, signed_on, create <first> <count> (value: the first's creation time), features <n>,
// diverged, settled (not diverged, caught up), digest (value: it), corrupt and repaired <site>
// <host> <seq>; a raw peer's ping, hello (sender: until the receiver answers), recv <n> <window>
// (receiver), send <n> <window> (sender; value: the first send's time).
int RunPeer(const PeerOptions& options);

}  // namespace dt::hostsbench

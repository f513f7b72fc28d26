// PduAuthenticator: signs sent PDUs and verifies received ones (MAC, sender, freshness, replay).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pdu/auth_trailer.h"
#include "pdu/clock_watch.h"
#include "pdu/exercise_key.h"
#include "pdu/replay_window.h"
#include "pdu/validation.h"

namespace dt {

// Milliseconds since the Unix epoch by the system clock (UTC).
int64_t WallClockMs();

// Default tolerance between a PDU's send time and the receiver's clock.
inline constexpr std::chrono::milliseconds kDefaultClockTolerance{30000};

struct PduAuthConfig {
  // The exercise key; null: no authentication (PDUs go out without a trailer and a received
  // trailer is refused as trailing bytes), as an exercise with [auth] mode = "none".
  std::shared_ptr<const ExerciseKey> key;
  // A PDU whose send time is further than this from the receiver's wall clock, either way, is
  // dropped as stale. The hosts' clocks must agree to well within it (NTP).
  std::chrono::milliseconds clock_tolerance = kDefaultClockTolerance;
  // Wall clock, ms since the Unix epoch; tests pass their own.
  std::function<int64_t()> wall_clock_ms = [] { return WallClockMs(); };
  // This sender's incarnation; 0: wall_clock_ms() when the authenticator is made (the process's
  // start, so a restarted process is a newer incarnation).
  uint64_t incarnation = 0;
  // The exercise's process names by address, for the clock-skew log lines (ClockWatch).
  std::map<NodeAddress, std::string> sender_names = {};
};

// Appends the trailer (auth_trailer.h) to every PDU a bus sends and checks the trailer of every
// PDU it receives before anything decodes it. Transport-independent: it works on the bytes a
// Transport carries, so LCM and DDS are authenticated alike. Not thread-safe (as PduBus).
//
// A received PDU is dropped, in this order of checks, as
//   oversized        more than kMaxPduBytes bytes, trailer included;
//   unauthenticated  no trailer (too short, or no magic where the trailer begins);
//   bad_mac          the MAC is not the exercise key's over the PDU and the trailer fields;
//   sender_mismatch  the trailer's sender is not the PDU's sender field;
//   stale            |send time - receiver's wall clock| > clock_tolerance;
//   replayed         ReplayWindow refuses (incarnation, sequence) for the trailer's sender.
// A sender from which nothing was accepted for more than 2 x clock_tolerance is forgotten
// (everything it sent before then is stale now), so a process restarted after its clock went
// back is heard again after at most that long, and the table of senders stays small.
//
// A PDU dropped as stale is most often a host whose clock is off, not an attack (only key holders
// pass the MAC check before it): ClockWatch keeps each such sender's offset, logs it and tells
// whether this host's own clock is the likely culprit (clock_report()).
class PduAuthenticator {
 public:
  // Throws std::invalid_argument if config.key is null, the tolerance is not positive or the
  // clock is empty.
  PduAuthenticator(NodeAddress local, PduAuthConfig config);

  // Appends the trailer for the LCM-encoded PDU in `bytes` (the next sequence, now).
  void Sign(std::vector<uint8_t>& bytes);

  // Checks received bytes. nullopt: authentic and new; `pdu` is then the LCM-encoded PDU (the
  // bytes without the trailer), to decode and validate as usual. Never throws.
  std::optional<Rejection> Verify(std::span<const uint8_t> bytes, std::span<const uint8_t>& pdu);

  uint64_t incarnation() const { return incarnation_; }
  uint64_t last_sequence() const { return sequence_; }
  const PduAuthConfig& config() const { return config_; }
  size_t senders_tracked() const { return senders_.size(); }
  // The senders whose PDUs are dropped as stale now, and the verdict on this host's clock.
  ClockReport clock_report() const;
  const ClockWatch& clock_watch() const { return clock_watch_; }

 private:
  struct Sender {
    ReplayWindow window;
    int64_t last_accepted_ms = 0;  // receiver's wall clock
  };

  // Senders other than `except` from which a PDU was accepted within kClockWatchWindow: they
  // agree with this host's clock.
  size_t AgreeingSenders(int64_t now_ms, std::optional<NodeAddress> except) const;

  NodeAddress local_;
  PduAuthConfig config_;
  uint64_t incarnation_;
  uint64_t sequence_ = 0;
  std::map<NodeAddress, Sender> senders_;
  ClockWatch clock_watch_;
};

}  // namespace dt

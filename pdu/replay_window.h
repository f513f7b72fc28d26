// ReplayWindow: which sequence numbers of one sender were already accepted (anti-replay).
#pragma once

#include <array>
#include <cstdint>

namespace dt {

// Tracks one sender: its newest incarnation and, within it, the highest sequence accepted plus a
// bitmap of the kSize sequences at and below it (a sliding window, as IPsec's). A PDU is new
// when its incarnation is newer than the one held (the window restarts), or it is the same
// incarnation and its sequence is above the highest, or within the window and not yet seen.
// Everything else is a replay: an older incarnation, a sequence seen before, or one so far
// behind that the window no longer says whether it was seen. When the window (re)starts, every
// sequence below the first one heard counts as seen: a receiver that joins late never takes
// what the sender sent before it was heard (a recording of it, replayed), at the price of
// refusing a PDU that overtook its predecessor just then (the protocol recovers it by playback).
class ReplayWindow {
 public:
  // Sequences kept behind the highest: reordering deeper than this is refused. Large enough for
  // the fault injector's reordering and a burst overtaken on a busy socket; 128 bytes per sender.
  static constexpr uint64_t kSize = 1024;

  enum class Verdict { kNew, kOlderIncarnation, kSeen, kBehindWindow };

  // Decides and, for kNew, records the sequence.
  Verdict Accept(uint64_t incarnation, uint64_t sequence);

  bool empty() const { return !has_; }
  uint64_t incarnation() const { return incarnation_; }
  uint64_t highest() const { return highest_; }

 private:
  bool Test(uint64_t sequence) const;
  void Set(uint64_t sequence);
  void Clear(uint64_t sequence);

  bool has_ = false;
  uint64_t incarnation_ = 0;
  uint64_t highest_ = 0;
  // Bit (s % kSize) is set when sequence s, highest - kSize < s <= highest, was accepted.
  std::array<uint64_t, kSize / 64> bits_{};
};

}  // namespace dt

// ChangeLog: the changes one author made, as a replica holds them, and the gap-free point.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <memory_resource>
#include <optional>
#include <vector>

#include "base/feature_id.h"
#include "engine/change.h"

namespace dt {

// Keyed by the author's change sequence. The gap-free point is the highest s such that 1..s are
// all held; max_known is the highest sequence held here or claimed by a live reporter.
//
// An author's sequences arrive almost in order, so they are held in slots indexed by sequence
// (no allocation or tree search per change); a change too far past the last slot (a rejoining
// node hearing live changes before its catch-up, or bad input) is kept aside in a map instead of
// opening a long run of empty slots. A held change never moves: pointers from Find and Range stay
// valid while more changes arrive.
class ChangeLog {
 public:
  // The slots' chunks come from `memory` (a replica's arena, base/growing_arena.h: a log only
  // grows), which must outlive the log.
  explicit ChangeLog(std::pmr::memory_resource* memory = std::pmr::new_delete_resource())
      : memory_(memory) {}

  // False (and nothing changes) if the sequence is already held.
  bool Insert(const Change& change);
  // Puts `change` in the slot of its sequence in place of the change held there (anti-entropy's
  // repair, docs/protocol.md); the gap-free point and pointers to the slot are unchanged. False
  // (and nothing changes) if the sequence is not held.
  bool Replace(const Change& change);
  // Takes the change held in slot `seq` out of the log (an observer dropping a change nobody else
  // holds, docs/protocol.md "Observers"): the gap-free point falls below `seq` if it was above,
  // and max_held to the highest change still held. Pointers to other slots stay valid. Nullopt
  // (and nothing changes) if the sequence is not held.
  std::optional<Change> Remove(int64_t seq);
  const Change* Find(int64_t seq) const;
  // Held changes with start <= seq <= end, in sequence order.
  std::vector<const Change*> Range(int64_t start, int64_t end) const;

  // A live replica (the author itself, a server, a peer answering a sign-on) says it holds the
  // author's changes up to `seq`. The latest report of each reporter counts, so an author that
  // restarted after losing changes nobody else held takes its claim back.
  void Report(NodeAddress reporter, int64_t seq) { reports_[reporter] = seq; }
  // A peer's anti-entropy summary says it holds a change up to `seq` (maybe beyond a gap): kept
  // apart from Report, whose claims may go down, so the two do not overwrite each other.
  void ReportHeld(NodeAddress holder, int64_t seq) { held_by_[holder] = seq; }
  // A reporter that fell silent no longer vouches for anything.
  void ForgetReporter(NodeAddress reporter) {
    reports_.erase(reporter);
    held_by_.erase(reporter);
  }
  // Claims beyond the highest change held that nobody backed with the change: dropped when the
  // gap they open is given up on (docs/protocol.md, "Lost changes").
  void ForgetClaimsBeyondHeld() {
    std::erase_if(reports_, [&](const auto& r) { return r.second > max_held_; });
    std::erase_if(held_by_, [&](const auto& r) { return r.second > max_held_; });
  }
  const std::map<NodeAddress, int64_t>& reports() const { return reports_; }
  const std::map<NodeAddress, int64_t>& held_by() const { return held_by_; }
  // Sequences up to `seq` exist whoever reports them: a node knows how far its own changes went
  // (its own or a previous incarnation's), even when every reporter of them falls silent.
  void RaiseFloor(int64_t seq) { floor_ = std::max(floor_, seq); }
  int64_t contiguous() const { return contiguous_; }
  int64_t max_known() const;
  int64_t max_held() const { return max_held_; }
  bool has_gap() const { return max_known() > contiguous_; }
  // The first missing sequence after the gap-free point and the end of that missing run (capped
  // at max_known); {0, -1} when there is no gap.
  std::pair<int64_t, int64_t> FirstGap() const;
  size_t size() const { return held_; }

  // A change at most this far past the last slot gets a slot (and the empty ones before it).
  static constexpr int64_t kMaxSlotJump = 256;

 private:
  // Slot i holds sequence i + 1, in fixed chunks of kChunkSlots: adding slots never moves a held
  // change, and a change costs no allocation of its own (a deque of a type this large allocates a
  // block for every one or two, a malloc per change on the receive path).
  static constexpr size_t kChunkSlots = 32;
  using Chunk = std::array<std::optional<Change>, kChunkSlots>;
  // Destroys a chunk and gives its memory back to the resource it came from.
  struct ChunkDeleter {
    std::pmr::memory_resource* memory;
    void operator()(Chunk* chunk) const;
  };
  std::optional<Change>& slot(size_t i) { return (*chunks_[i / kChunkSlots])[i % kChunkSlots]; }
  const std::optional<Change>& slot(size_t i) const {
    return (*chunks_[i / kChunkSlots])[i % kChunkSlots];
  }
  // Opens empty slots up to `count` (never fewer than there are).
  void GrowSlots(size_t count);
  std::pmr::memory_resource* memory_;
  std::vector<std::unique_ptr<Chunk, ChunkDeleter>> chunks_;
  size_t slot_count_ = 0;
  std::map<int64_t, Change> aside_;  // held changes that got no slot
  size_t held_ = 0;
  int64_t max_held_ = 0;
  int64_t contiguous_ = 0;
  std::map<NodeAddress, int64_t> reports_;
  std::map<NodeAddress, int64_t> held_by_;
  int64_t floor_ = 0;
};

}  // namespace dt

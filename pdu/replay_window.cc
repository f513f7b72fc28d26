#include "pdu/replay_window.h"

namespace dt {

bool ReplayWindow::Test(uint64_t s) const { return (bits_[(s % kSize) / 64] >> (s % 64)) & 1u; }
void ReplayWindow::Set(uint64_t s) { bits_[(s % kSize) / 64] |= uint64_t{1} << (s % 64); }
void ReplayWindow::Clear(uint64_t s) { bits_[(s % kSize) / 64] &= ~(uint64_t{1} << (s % 64)); }

ReplayWindow::Verdict ReplayWindow::Accept(uint64_t incarnation, uint64_t sequence) {
  if (has_ && incarnation < incarnation_) return Verdict::kOlderIncarnation;
  if (!has_ || incarnation > incarnation_) {
    has_ = true;
    incarnation_ = incarnation;
    highest_ = sequence;
    bits_.fill(~uint64_t{0});  // the first sequence heard and everything before it
    return Verdict::kNew;
  }
  if (sequence > highest_) {
    const uint64_t advance = sequence - highest_;
    if (advance >= kSize) {
      bits_.fill(0);
    } else {
      // The slots the window slides over belonged to sequences now out of it.
      for (uint64_t s = highest_ + 1; s <= sequence; ++s) Clear(s);
    }
    highest_ = sequence;
    Set(sequence);
    return Verdict::kNew;
  }
  if (highest_ - sequence >= kSize) return Verdict::kBehindWindow;
  if (Test(sequence)) return Verdict::kSeen;
  Set(sequence);
  return Verdict::kNew;
}

}  // namespace dt

// Tests ReplayWindow: new, seen, reordered, behind the window, and incarnations.
#include "pdu/replay_window.h"

#include <gtest/gtest.h>

namespace dt {
namespace {

using V = ReplayWindow::Verdict;

TEST(ReplayWindow, AcceptsEachSequenceOnce) {
  ReplayWindow w;
  EXPECT_TRUE(w.empty());
  EXPECT_EQ(w.Accept(10, 1), V::kNew);
  EXPECT_EQ(w.Accept(10, 2), V::kNew);
  EXPECT_EQ(w.Accept(10, 2), V::kSeen);
  EXPECT_EQ(w.Accept(10, 1), V::kSeen);
  EXPECT_EQ(w.highest(), 2u);
}

TEST(ReplayWindow, AcceptsReorderingWithinTheWindowOnce) {
  ReplayWindow w;
  EXPECT_EQ(w.Accept(1, 100), V::kNew);
  EXPECT_EQ(w.Accept(1, 100 + ReplayWindow::kSize - 1), V::kNew);
  // 100 is still inside the window: seen. 101..: never seen, accepted once.
  EXPECT_EQ(w.Accept(1, 100), V::kSeen);
  EXPECT_EQ(w.Accept(1, 101), V::kNew);
  EXPECT_EQ(w.Accept(1, 101), V::kSeen);
  EXPECT_EQ(w.Accept(1, 99), V::kBehindWindow);  // highest - 99 = kSize
}

TEST(ReplayWindow, RefusesSequencesBelowTheFirstHeard) {
  // A receiver that starts late first hears some sequence; what the sender sent before it (a
  // recording of it) is refused, but gaps opened after the first are filled once.
  ReplayWindow w;
  EXPECT_EQ(w.Accept(1, 100), V::kNew);
  EXPECT_EQ(w.Accept(1, 90), V::kSeen);
  EXPECT_EQ(w.Accept(1, 99), V::kSeen);
  EXPECT_EQ(w.Accept(1, 103), V::kNew);
  EXPECT_EQ(w.Accept(1, 101), V::kNew);
  EXPECT_EQ(w.Accept(1, 101), V::kSeen);
  EXPECT_EQ(w.highest(), 103u);
  // The same after a restart: the new incarnation's window starts at its first sequence heard.
  EXPECT_EQ(w.Accept(2, 7), V::kNew);
  EXPECT_EQ(w.Accept(2, 6), V::kSeen);
}

TEST(ReplayWindow, RefusesWhatIsTooFarBehind) {
  ReplayWindow w;
  EXPECT_EQ(w.Accept(1, 1), V::kNew);
  EXPECT_EQ(w.Accept(1, 5000), V::kNew);  // a jump past the whole window: none of it was seen
  EXPECT_EQ(w.Accept(1, 5000 - ReplayWindow::kSize + 1), V::kNew);  // the oldest slot kept
  EXPECT_EQ(w.Accept(1, 5000 - ReplayWindow::kSize), V::kBehindWindow);
  EXPECT_EQ(w.Accept(1, 1), V::kBehindWindow);
}

TEST(ReplayWindow, SlidingClearsTheSlotsItPasses) {
  ReplayWindow w;
  EXPECT_EQ(w.Accept(1, 1), V::kNew);
  EXPECT_EQ(w.Accept(1, 3), V::kNew);
  // 3 + kSize reuses 3's slot; 2 + kSize reuses 2's, which was never seen.
  EXPECT_EQ(w.Accept(1, 3 + ReplayWindow::kSize), V::kNew);
  EXPECT_EQ(w.Accept(1, 3), V::kBehindWindow);
  EXPECT_EQ(w.Accept(1, 2 + ReplayWindow::kSize), V::kNew);
  EXPECT_EQ(w.Accept(1, 4), V::kNew);  // still in the window, never seen
  EXPECT_EQ(w.Accept(1, 4), V::kSeen);
  // A jump of more than the window forgets everything behind it.
  EXPECT_EQ(w.Accept(1, 100000), V::kNew);
  EXPECT_EQ(w.Accept(1, 100000 - 1), V::kNew);
  EXPECT_EQ(w.Accept(1, 100000 - 1), V::kSeen);
}

TEST(ReplayWindow, ANewerIncarnationRestartsAndAnOlderOneIsRefused) {
  ReplayWindow w;
  EXPECT_EQ(w.Accept(1000, 50), V::kNew);
  EXPECT_EQ(w.Accept(2000, 1), V::kNew);  // the sender restarted
  EXPECT_EQ(w.incarnation(), 2000u);
  EXPECT_EQ(w.Accept(2000, 1), V::kSeen);
  EXPECT_EQ(w.Accept(1000, 51), V::kOlderIncarnation);  // its previous life, replayed
  EXPECT_EQ(w.Accept(2000, 2), V::kNew);
}

}  // namespace
}  // namespace dt

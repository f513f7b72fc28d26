// Tests what a receiver makes of PDUs dropped as stale (pdu/clock_watch.h): the sender and its
// offset in the log and the clock report, the rate limit, the end of the skew, and when it
// blames its own clock. Every host's wall clock is injected.
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <spdlog/sinks/ostream_sink.h>

#include "log/log.h"
#include "pdu/pdu_auth.h"
#include "pdu/test/sample_pdus.h"

namespace dt {
namespace {

constexpr int64_t kStartMs = 1'700'000'000'000;  // a wall-clock time, ms since the epoch
constexpr NodeAddress kReceiver{2, 2};
constexpr NodeAddress kServer{1, 100};
constexpr NodeAddress kNode1{1, 1};
constexpr NodeAddress kNode3{1, 3};

// Copies every log line written while it lives (the message only, one per line).
class LogCapture {
 public:
  LogCapture() : sink_(std::make_shared<spdlog::sinks::ostream_sink_st>(out_)) {
    sink_->set_pattern("%l %v");
    log::Logger().sinks().push_back(sink_);
  }
  ~LogCapture() { std::erase(log::Logger().sinks(), sink_); }

  std::vector<std::string> Lines() const {
    std::vector<std::string> lines;
    std::istringstream in(out_.str());
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
  }
  // The lines containing `text`.
  std::vector<std::string> With(const std::string& text) const {
    std::vector<std::string> out;
    for (const std::string& l : Lines()) {
      if (l.find(text) != std::string::npos) out.push_back(l);
    }
    return out;
  }

 private:
  std::ostringstream out_;
  std::shared_ptr<spdlog::sinks::ostream_sink_st> sink_;
};

// One host of the exercise: an authenticator with its own wall clock, signing the sample
// Construct as itself.
class Host {
 public:
  Host(NodeAddress address, std::shared_ptr<const ExerciseKey> key, int64_t clock_offset_ms,
       const int64_t* true_now_ms)
      : address_(address), offset_ms_(clock_offset_ms), true_now_ms_(true_now_ms) {
    PduAuthConfig c;
    c.key = std::move(key);
    c.wall_clock_ms = [this] { return *true_now_ms_ + offset_ms_; };
    c.sender_names = {{kServer, "server"}, {kNode1, "node-1"}, {kNode3, "node-3"}};
    auth_ = std::make_unique<PduAuthenticator>(address, c);
  }

  std::vector<uint8_t> Signed() {
    dtpdu::construct_t pdu = sample::Construct();
    pdu.sender = ToPdu(address_);
    std::vector<uint8_t> bytes = EncodePdu(pdu);
    auth_->Sign(bytes);
    return bytes;
  }

  // Verifies a PDU `from` signs now; true if accepted.
  bool Receive(Host& from) {
    const std::vector<uint8_t> bytes = from.Signed();
    std::span<const uint8_t> pdu;
    return !auth_->Verify(bytes, pdu).has_value();
  }

  void set_offset_ms(int64_t ms) { offset_ms_ = ms; }
  const PduAuthenticator& auth() const { return *auth_; }

 private:
  NodeAddress address_;
  int64_t offset_ms_;
  const int64_t* true_now_ms_;
  std::unique_ptr<PduAuthenticator> auth_;
};

class ClockSkewTest : public ::testing::Test {
 protected:
  // A host whose clock is offset_ms ahead of the true time (behind if negative).
  std::unique_ptr<Host> MakeHost(NodeAddress a, int64_t offset_ms = 0) {
    return std::make_unique<Host>(a, key_, offset_ms, &now_ms_);
  }

  int64_t now_ms_ = kStartMs;  // the true time
  std::shared_ptr<const ExerciseKey> key_ =
      std::make_shared<const ExerciseKey>(std::vector<uint8_t>(32, 0x11));
  LogCapture log_;
};

TEST_F(ClockSkewTest, ASenderAheadIsNamedWithItsOffset) {
  auto receiver = MakeHost(kReceiver);
  auto node3 = MakeHost(kNode3, 45'200);
  EXPECT_FALSE(receiver->Receive(*node3));

  const ClockReport r = receiver->auth().clock_report();
  ASSERT_EQ(r.suspects.size(), 1u);
  EXPECT_EQ(r.suspects[0].sender, kNode3);
  EXPECT_LE(std::llabs(r.suspects[0].offset_ms - 45'000), 1000) << r.suspects[0].offset_ms;
  EXPECT_EQ(r.suspects[0].stale, 1u);
  EXPECT_EQ(r.worst_offset_ms(), r.suspects[0].offset_ms);
  EXPECT_EQ(r.own_offset_ms, std::nullopt);  // one sender: either clock may be wrong

  const auto lines = log_.With("clock skew:");
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0],
            "warning clock skew: PDUs from 1:3 (node-3) are stamped 45.2 s ahead of this host's "
            "clock, beyond the exercise's 30 s tolerance: they are dropped until the clocks agree "
            "(check NTP on both hosts); 1 dropped so far");
  EXPECT_EQ(receiver->auth().clock_watch().lines_logged(), 1u);
}

TEST_F(ClockSkewTest, ASenderBehindIsNamedToo) {
  auto receiver = MakeHost(kReceiver);
  auto stranger = MakeHost({7, 7}, -31'000);  // no name in the exercise
  EXPECT_FALSE(receiver->Receive(*stranger));
  const ClockReport r = receiver->auth().clock_report();
  ASSERT_EQ(r.suspects.size(), 1u);
  EXPECT_LE(std::llabs(r.suspects[0].offset_ms + 31'000), 1000);
  EXPECT_EQ(r.worst_offset_ms(), r.suspects[0].offset_ms);
  const auto lines = log_.With("PDUs from 7:7 are stamped 31.0 s behind this host's clock");
  EXPECT_EQ(lines.size(), 1u);
}

TEST_F(ClockSkewTest, TheLineIsRepeatedAtMostEveryTenSecondsWhileItLasts) {
  auto receiver = MakeHost(kReceiver);
  auto node3 = MakeHost(kNode3, 45'000);
  // 25 s of a PDU every 100 ms: lines at 0, 10 and 20 s, each with the count so far.
  for (int i = 0; i < 250; ++i) {
    EXPECT_FALSE(receiver->Receive(*node3));
    now_ms_ += 100;
  }
  const auto lines = log_.With("PDUs from 1:3 (node-3)");
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_NE(lines[0].find("; 1 dropped so far"), std::string::npos) << lines[0];
  EXPECT_NE(lines[1].find("; 101 dropped so far"), std::string::npos) << lines[1];
  EXPECT_NE(lines[2].find("; 201 dropped so far"), std::string::npos) << lines[2];
  EXPECT_EQ(receiver->auth().clock_watch().lines_logged(), 3u);
  EXPECT_EQ(receiver->auth().clock_report().suspects.at(0).stale, 250u);
}

TEST_F(ClockSkewTest, TheEndOfTheSkewIsSaidAndClearsTheReport) {
  auto receiver = MakeHost(kReceiver);
  auto node3 = MakeHost(kNode3, 45'000);
  EXPECT_FALSE(receiver->Receive(*node3));
  now_ms_ += 1000;
  node3->set_offset_ms(20);  // NTP stepped its clock
  EXPECT_TRUE(receiver->Receive(*node3));
  EXPECT_TRUE(receiver->auth().clock_report().suspects.empty());
  EXPECT_EQ(log_.With("clock skew over: PDUs from 1:3 (node-3) are accepted again").size(), 1u);
  // Skewed again at once: the warning waits out the interval since the last one.
  node3->set_offset_ms(45'000);
  now_ms_ += 1000;
  EXPECT_FALSE(receiver->Receive(*node3));
  EXPECT_EQ(receiver->auth().clock_report().suspects.size(), 1u);
  EXPECT_EQ(log_.With("clock skew: PDUs from 1:3").size(), 1u);
  now_ms_ += kClockLogInterval.count();
  EXPECT_FALSE(receiver->Receive(*node3));
  EXPECT_EQ(log_.With("clock skew: PDUs from 1:3").size(), 2u);
}

TEST_F(ClockSkewTest, ASuspectNotHeardForTheWindowLeavesTheReport) {
  auto receiver = MakeHost(kReceiver);
  auto node3 = MakeHost(kNode3, 45'000);
  EXPECT_FALSE(receiver->Receive(*node3));
  now_ms_ += kClockWatchWindow.count();
  EXPECT_EQ(receiver->auth().clock_report().suspects.size(), 1u);
  now_ms_ += 1;
  EXPECT_TRUE(receiver->auth().clock_report().suspects.empty());
}

TEST_F(ClockSkewTest, AHostAheadOfEveryOtherSenderBlamesItsOwnClock) {
  auto skewed = MakeHost(kNode3, 45'000);
  auto server = MakeHost(kServer);
  auto node1 = MakeHost(kNode1, 300);  // the others' clocks differ a little too
  for (int i = 0; i < 150; ++i) {      // 15 s
    EXPECT_FALSE(skewed->Receive(*server));
    EXPECT_FALSE(skewed->Receive(*node1));
    now_ms_ += 100;
  }
  const ClockReport r = skewed->auth().clock_report();
  ASSERT_TRUE(r.own_offset_ms.has_value());
  EXPECT_LE(std::llabs(*r.own_offset_ms - 45'000), 1000) << *r.own_offset_ms;
  ASSERT_EQ(r.suspects.size(), 2u);
  EXPECT_LT(r.suspects[0].offset_ms, -44'000);

  // The first sender heard is named alone (one sender could be the wrong one); from the second
  // on, one line blames this host and names them all, at most every 10 s.
  EXPECT_EQ(log_.With("clock skew: PDUs from").size(), 1u);
  const auto own = log_.With("this host's clock is probably");
  ASSERT_EQ(own.size(), 2u);
  EXPECT_EQ(own[0],
            "warning clock skew: every PDU received is stamped about 45 s behind this host's "
            "clock: this host's clock is probably 45 s ahead of the exercise (check NTP on this "
            "host); PDUs from 1:1 (node-1), 1:100 (server) are dropped until it agrees");
  EXPECT_EQ(skewed->auth().clock_watch().lines_logged(), 3u);

  // Its clock fixed, the next PDU accepted says so.
  skewed->set_offset_ms(0);
  EXPECT_TRUE(skewed->Receive(*server));
  EXPECT_EQ(log_.With("this host's clock agrees with it again").size(), 1u);
  EXPECT_EQ(skewed->auth().clock_report().own_offset_ms, std::nullopt);
}

TEST_F(ClockSkewTest, AHostBehindEveryoneSaysSo) {
  auto skewed = MakeHost(kNode3, -60'000);
  auto server = MakeHost(kServer);
  auto node1 = MakeHost(kNode1);
  EXPECT_FALSE(skewed->Receive(*server));
  EXPECT_FALSE(skewed->Receive(*node1));
  const ClockReport r = skewed->auth().clock_report();
  ASSERT_TRUE(r.own_offset_ms.has_value());
  EXPECT_LE(std::llabs(*r.own_offset_ms + 60'000), 1000);
  EXPECT_EQ(log_.With("every PDU received is stamped about 60 s ahead of this host's clock: this "
                      "host's clock is probably 60 s behind the exercise")
                .size(),
            1u);
}

TEST_F(ClockSkewTest, OneSenderOffInThreeIsItsOwnFault) {
  auto receiver = MakeHost(kReceiver);
  auto server = MakeHost(kServer);
  auto node1 = MakeHost(kNode1);
  auto node3 = MakeHost(kNode3, 45'000);
  for (int i = 0; i < 150; ++i) {
    EXPECT_TRUE(receiver->Receive(*server));
    EXPECT_TRUE(receiver->Receive(*node1));
    EXPECT_FALSE(receiver->Receive(*node3));
    now_ms_ += 100;
  }
  const ClockReport r = receiver->auth().clock_report();
  EXPECT_EQ(r.own_offset_ms, std::nullopt);
  ASSERT_EQ(r.suspects.size(), 1u);
  EXPECT_EQ(r.suspects[0].sender, kNode3);
  EXPECT_TRUE(log_.With("probably").empty());
  EXPECT_EQ(log_.With("PDUs from 1:3 (node-3) are stamped 45.0 s ahead").size(), 2u);
}

TEST_F(ClockSkewTest, SendersOffInOppositeWaysOrByDifferentAmountsBlameNoOne) {
  auto receiver = MakeHost(kReceiver);
  auto ahead = MakeHost(kServer, 45'000);
  auto behind = MakeHost(kNode1, -45'000);
  EXPECT_FALSE(receiver->Receive(*ahead));
  EXPECT_FALSE(receiver->Receive(*behind));
  EXPECT_EQ(receiver->auth().clock_report().own_offset_ms, std::nullopt);
  EXPECT_EQ(receiver->auth().clock_report().suspects.size(), 2u);

  auto receiver2 = MakeHost({2, 3});
  auto far = MakeHost(kServer, 100'000);
  auto near = MakeHost(kNode1, 40'000);  // 60 s apart: they would refuse each other too
  EXPECT_FALSE(receiver2->Receive(*far));
  EXPECT_FALSE(receiver2->Receive(*near));
  EXPECT_EQ(receiver2->auth().clock_report().own_offset_ms, std::nullopt);
  EXPECT_TRUE(log_.With("probably").empty());
}

}  // namespace
}  // namespace dt

// Tests the `status` reply's one definition: its text byte for byte, reading it back, and the
// errors of text that does not read.
#include "runtime/status_report.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

#include <fmt/format.h>

namespace dt {
namespace {

// Every field set, each to a value of its own, with repeated lines of every kind.
StatusReport FullReport() {
  StatusReport r;
  r.name = "node-2";
  r.address = {1, 2};
  r.role = NodeRole::kNode;
  r.require_server = true;
  r.signed_on = true;
  r.caught_up = false;
  r.diverged = true;
  r.diverged_since_ms = 1234;
  r.features = 7;
  r.digest = "0123456789abcdef0123456789abcdef";
  r.own_feature_number = 9;
  r.own_change_seq = 11;
  r.acknowledged_change_seq = 10;
  r.sent = 100;
  r.received = 200;
  r.rejected = 3;
  r.played_back = 4;
  r.applied = 5;
  r.ignored_stale = 6;
  r.fault_dropped = 8;
  r.drop_probability = 0.25;
  r.write_queued = 12;
  r.write_retried = 13;
  r.write_failed = 14;
  r.write_given_up = 15;
  r.voided = 16;
  r.gave_up = 17;
  r.refused_stranger = 18;
  r.refused_role = 19;
  r.refused_claim = 20;
  r.refused_lamport = 21;
  r.refused_ground = 22;
  r.ground_digest = "00112233445566778899aabbccddeeff";
  r.ground_source = "ground_file /ex/field.dtt";
  r.ground_refused = true;
  r.exercise_ground_digest = "ffeeddccbbaa99887766554433221100";
  r.ground_mismatches = {{{1, 3}, "0f0f0f0f0f0f0f0f0f0f0f0f0f0f0f0f"}};
  for (size_t i = 0; i < kRejectReasonCount; ++i) r.rejected_by_reason[i] = 1000 + i;
  r.authenticated = true;
  r.auth_senders = 4;
  r.clock_suspect_senders = 2;
  r.clock_worst_offset_ms = -45210;
  r.own_clock_suspect = true;
  r.own_clock_offset_ms = 45105;
  r.clock_suspects = {{{1, 1}, -45000, 284}, {{1, 100}, -45210, 647}};
  r.max_features = {{{1, 1}, 12}, {{1, 2}, 3}};
  r.divergences = {{{1, 1}, {1, 3}, 4, 9, true, 1500}, {{1, 2}, {1, 100}, 1, 2, false, 1600}};
  StatusReport::Vehicle tank;
  tank.index = 0;
  tank.type = "tank";
  tank.x_m = 12.345678;
  tank.z_m = 100.0;
  tank.y_m = -0.004;
  tank.heading_rad = 1.23456;
  tank.speed_mps = 5.5;
  tank.on_bridge = FeatureId{1, 1, 4};
  tank.alive = true;
  tank.model = VehicleModel::kPhysical;
  tank.damage = Damage::kImmobilised;
  StatusReport::Vehicle jeep;
  jeep.index = 1;
  jeep.type = "jeep";
  jeep.x_m = 50.0;
  jeep.z_m = 60.126;
  jeep.y_m = 3.0;
  jeep.heading_rad = -3.14159;
  jeep.speed_mps = 0.0;
  jeep.alive = false;
  jeep.model = VehicleModel::kLight;
  jeep.damage = Damage::kDestroyed;
  r.vehicles = {tank, jeep};
  r.other_lines = {{"local_vehicles", "2"}, {"remote_vehicles", "0"}};
  return r;
}

// FullReport's text, written from the format strings the status reply has always had: if the
// format drifts, this fails.
std::string FullReportText() {
  std::string s = fmt::format(
      "name {}\naddress {}\nrole {}\nrequire_server {}\nsigned_on {}\ncaught_up {}\n"
      "diverged {}\ndiverged_since_ms {}\nfeatures {}\ndigest {}\n"
      "own_feature_number {}\nown_change_seq {}\nacknowledged_change_seq {}\n"
      "sent {}\nreceived {}\nrejected {}\nplayed_back {}\napplied {}\nignored_stale {}\n"
      "fault_dropped {}\ndrop_probability {}\nwrite_queued {}\nwrite_retried {}\n"
      "write_failed {}\nwrite_given_up {}",
      "node-2", "1:2", "node", 1, 1, 0, 1, 1234, 7, "0123456789abcdef0123456789abcdef", 9, 11, 10,
      100, 200, 3, 4, 5, 6, 8, 0.25, 12, 13, 14, 15);
  s += fmt::format(
      "\nvoided {}\ngave_up {}\nrefused_stranger {}\nrefused_role {}\nrefused_claim "
      "{}\nrefused_lamport {}",
      16, 17, 18, 19, 20, 21);
  s += fmt::format(
      "\nrefused_ground {}\nground_digest {}\nground_source {}\nground_refused {}"
      "\nexercise_ground_digest {}",
      22, "00112233445566778899aabbccddeeff", "ground_file /ex/field.dtt", 1,
      "ffeeddccbbaa99887766554433221100");
  for (size_t i = 0; i < kRejectReasonCount; ++i) {
    s += fmt::format("\nrejected_{} {}", RejectReasonName(static_cast<RejectReason>(i)), 1000 + i);
  }
  s += fmt::format("\nauthenticated {}\nauth_senders {}", 1, 4);
  s += fmt::format(
      "\nclock_suspect_senders {}\nclock_worst_offset_ms {}\nown_clock_suspect {}"
      "\nown_clock_offset_ms {}",
      2, -45210, 1, 45105);
  s += "\nmax_feature 1:1 12"
       "\nmax_feature 1:2 3"
       "\nclock_suspect 1:1 offset_ms=-45000 stale=284"
       "\nclock_suspect 1:100 offset_ms=-45210 stale=647"
       "\nground_mismatch 1:3 digest=0f0f0f0f0f0f0f0f0f0f0f0f0f0f0f0f"
       "\ndivergence 1:1 with 1:3 changes 4..9 since_ms 1500"
       "\ndivergence 1:2 with 1:100 changes 1..2 (not located) since_ms 1600"
       "\nvehicle 0 tank x_m=12.35 z_m=100.00 y_m=-0.00 heading_rad=1.235 speed_mps=5.50 "
       "on_bridge=1:1:4 alive=1 model=physical damage=immobilised"
       "\nvehicle 1 jeep x_m=50.00 z_m=60.13 y_m=3.00 heading_rad=-3.142 speed_mps=0.00 "
       "on_bridge=- alive=0 model=light damage=destroyed"
       "\nlocal_vehicles 2"
       "\nremote_vehicles 0";
  return s;
}

std::string ErrorOf(std::string_view text) {
  Result<StatusReport> r = StatusReport::Parse(text);
  return r ? std::string() : r.error().message;
}

// The text with the line of `key` replaced by `line` (or removed when `line` is empty).
std::string WithLine(const std::string& text, const std::string& key, const std::string& line) {
  const size_t at = text.find("\n" + key + " ");
  EXPECT_NE(at, std::string::npos) << key;
  const size_t end = text.find('\n', at + 1);
  return text.substr(0, at) + (line.empty() ? "" : "\n" + line) +
         (end == std::string::npos ? "" : text.substr(end));
}

TEST(StatusReportTest, TextIsTodaysFormatByteForByte) {
  EXPECT_EQ(FullReport().ToText(), FullReportText());
}

TEST(StatusReportTest, TextReadsBackToTheSameText) {
  const std::string text = FullReport().ToText();
  Result<StatusReport> parsed = StatusReport::Parse(text);
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_EQ(parsed.value().ToText(), text);
  // Fields whose text is exact come back equal; vehicle poses come back rounded as written.
  const StatusReport& p = parsed.value();
  EXPECT_EQ(p.name, "node-2");
  EXPECT_EQ(p.address, (NodeAddress{1, 2}));
  EXPECT_EQ(p.role, NodeRole::kNode);
  EXPECT_EQ(p.diverged_since_ms, 1234);
  EXPECT_EQ(p.acknowledged_change_seq, 10);
  EXPECT_EQ(p.drop_probability, 0.25);
  EXPECT_EQ(p.rejected_by_reason, FullReport().rejected_by_reason);
  EXPECT_EQ(p.max_features, FullReport().max_features);
  EXPECT_EQ(p.clock_suspects, FullReport().clock_suspects);
  EXPECT_EQ(p.clock_worst_offset_ms, -45210);
  EXPECT_TRUE(p.own_clock_suspect);
  EXPECT_EQ(p.own_clock_offset_ms, 45105);
  EXPECT_EQ(p.divergences, FullReport().divergences);
  EXPECT_EQ(p.other_lines, FullReport().other_lines);
  ASSERT_EQ(p.vehicles.size(), 2u);
  EXPECT_EQ(p.vehicles[0].x_m, 12.35);
  EXPECT_EQ(p.vehicles[0].on_bridge, (FeatureId{1, 1, 4}));
  EXPECT_EQ(p.vehicles[0].damage, Damage::kImmobilised);
  EXPECT_FALSE(p.vehicles[1].on_bridge);
  EXPECT_FALSE(p.vehicles[1].alive);
  EXPECT_EQ(p.vehicles[1].model, VehicleModel::kLight);
  // Once rounded, a report reads back equal.
  EXPECT_EQ(StatusReport::Parse(p.ToText()).value(), p);
}

TEST(StatusReportTest, AReportWithNoRepeatedLinesReadsBack) {
  StatusReport r;
  r.name = "server";
  r.role = NodeRole::kServer;
  r.digest = "d";
  Result<StatusReport> parsed = StatusReport::Parse(r.ToText());
  ASSERT_TRUE(parsed) << parsed.error().message;
  EXPECT_EQ(parsed.value(), r);
}

TEST(StatusReportTest, MissingTruncatedAndNonNumericTextNamesTheKey) {
  const std::string text = FullReportText();
  EXPECT_EQ(ErrorOf(""), "status has no \"name\" line");
  EXPECT_EQ(ErrorOf("\n"), "status has no \"name\" line");
  // Cut off after a whole line: the first key missing is named.
  EXPECT_EQ(ErrorOf(text.substr(0, text.find("\nreceived "))), "status has no \"received\" line");
  EXPECT_EQ(ErrorOf(WithLine(text, "digest", "")), "status has no \"digest\" line");
  // Cut inside a line.
  EXPECT_EQ(ErrorOf(text.substr(0, text.find("\nreceived ") + 5)),
            "status line \"rece\" is not \"key value\"");
  EXPECT_EQ(ErrorOf(WithLine(text, "acknowledged_change_seq", "acknowledged_change_seq abc")),
            "status \"acknowledged_change_seq\" value \"abc\" is not a whole number");
  EXPECT_EQ(ErrorOf(WithLine(text, "sent", "sent -1")),
            "status \"sent\" value \"-1\" is not a whole number >= 0");
  EXPECT_EQ(ErrorOf(WithLine(text, "features", "features 12x")),
            "status \"features\" value \"12x\" is not a whole number >= 0");
  EXPECT_EQ(ErrorOf(WithLine(text, "caught_up", "caught_up 2")),
            "status \"caught_up\" value \"2\" is not 1 or 0");
  EXPECT_EQ(ErrorOf(WithLine(text, "drop_probability", "drop_probability half")),
            "status \"drop_probability\" value \"half\" is not a number");
  EXPECT_EQ(ErrorOf(WithLine(text, "address", "address 1-2")),
            "status \"address\" value \"1-2\" is not site:host");
  EXPECT_EQ(ErrorOf(WithLine(text, "role", "role boss")),
            "status \"role\" value \"boss\" is not node, server, standby or observer");
  EXPECT_EQ(ErrorOf(WithLine(text, "rejected_stale", "rejected_stale ")),
            "status \"rejected_stale\" value \"\" is not a whole number >= 0");
  EXPECT_EQ(ErrorOf(text + "\ndigest again"),
            "status line \"digest again\" repeats the key \"digest\"");
  EXPECT_NE(ErrorOf(text + "\nmax_feature 1:3").find("status \"max_feature\" value \"1:3\""),
            std::string::npos);
  EXPECT_EQ(ErrorOf(WithLine(text, "clock_worst_offset_ms", "clock_worst_offset_ms 45.2")),
            "status \"clock_worst_offset_ms\" value \"45.2\" is not a whole number");
  EXPECT_EQ(ErrorOf(WithLine(text, "own_clock_suspect", "")),
            "status has no \"own_clock_suspect\" line");
  for (const char* bad :
       {"1:3 offset_ms=45000", "1:3 45000 stale=1", "1:3 offset_ms=4s stale=1",
        "1:3 offset_ms=45000 stale=-1", "x offset_ms=1 stale=1", "1:3 offset_ms=1 stale=1 more"}) {
    EXPECT_EQ(ErrorOf(text + "\nclock_suspect " + bad),
              fmt::format("status \"clock_suspect\" value \"{}\" is not <site:host> "
                          "offset_ms=<ms> stale=<n>",
                          bad));
  }
  for (const char* bad : {"1:3", "1:3 digest=", "x digest=00", "1:3 0f0f"}) {
    EXPECT_EQ(ErrorOf(text + "\nground_mismatch " + bad),
              fmt::format("status line \"ground_mismatch {}\" is not \"ground_mismatch "
                          "<site:host> digest=<hex>\"",
                          bad));
  }
  EXPECT_NE(ErrorOf(text + "\ndivergence 1:1 with 1:3 changes 4-9 since_ms 1")
                .find("status \"divergence\" value \"1:1 with 1:3 changes 4-9 since_ms 1\""),
            std::string::npos);
  const std::string bad_vehicle =
      "vehicle 2 tank x_m=1.00 z_m=nope y_m=0.00 heading_rad=0.000 "
      "speed_mps=0.00 on_bridge=- alive=1 model=physical damage=none";
  EXPECT_NE(ErrorOf(text + "\n" + bad_vehicle).find("status \"vehicle\" value \"2 tank x_m="),
            std::string::npos);
  EXPECT_NE(ErrorOf(text + "\nvehicle 2 tank").find("status \"vehicle\""), std::string::npos);
}

TEST(StatusReportTest, NoTextCrashesIt) {
  const std::string text = FullReportText();
  // Every prefix: those that end before the last single-line key are refused.
  const size_t last_single = text.find("\nown_clock_offset_ms ");
  for (size_t n = 0; n <= text.size(); ++n) {
    Result<StatusReport> r = StatusReport::Parse(std::string_view(text).substr(0, n));
    if (n <= last_single) {
      EXPECT_FALSE(r) << n;
    }
  }
  // Random text, mostly of the characters status is made of, and the text with bytes changed.
  constexpr std::string_view kAlphabet = " \n:.=-_0123456789abcdeilmnorstvx()";
  std::mt19937_64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    std::string s = text;
    if (i % 2 == 0) {
      s.resize(rng() % 300);
      for (char& c : s) c = kAlphabet[rng() % kAlphabet.size()];
    }
    for (int k = 0; k < 8 && !s.empty(); ++k) s[rng() % s.size()] = static_cast<char>(rng() % 256);
    (void)StatusReport::Parse(s);
  }
}

TEST(StatusReportTest, UnknownKeysAreKeptAndWrittenLast) {
  const std::string text = FullReportText();
  // A key from a newer writer in the middle of the common lines.
  Result<StatusReport> r = StatusReport::Parse(WithLine(text, "voided", "voided 16\nnew_key 4 5"));
  ASSERT_TRUE(r) << r.error().message;
  ASSERT_EQ(r.value().other_lines.size(), 3u);
  EXPECT_EQ(r.value().other_lines[0], (std::pair<std::string, std::string>{"new_key", "4 5"}));
  EXPECT_EQ(r.value().ToText(), text.substr(0, text.find("\nlocal_vehicles")) +
                                    "\nnew_key 4 5\nlocal_vehicles 2\nremote_vehicles 0");
  // A trailing newline is no line.
  r = StatusReport::Parse(text + "\n");
  ASSERT_TRUE(r) << r.error().message;
  EXPECT_EQ(r.value().ToText(), text);
}

}  // namespace
}  // namespace dt

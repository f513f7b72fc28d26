#include "launcher/drill_runner.h"

#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "render/montage.h"
#include "render/png_io.h"
#include "runtime/control_client.h"
#include "runtime/control_command.h"

namespace dt {
namespace {

// Child lines worth showing on the drill's own output (everything goes to <run_dir>/<name>.log).
bool Notable(std::string_view line) {
  return line.rfind("READY ", 0) == 0 || line.find(" warning ") != std::string_view::npos ||
         line.find(" error ") != std::string_view::npos ||
         line.find(" critical ") != std::string_view::npos || line.rfind("dt_", 0) == 0;
}

// A sanitizer's report in a child's output (asan-ubsan build, docs/testing.md).
bool SanitizerReport(std::string_view line) {
  return line.find("runtime error:") != std::string_view::npos ||
         line.find("ERROR: AddressSanitizer") != std::string_view::npos ||
         line.find("ERROR: LeakSanitizer") != std::string_view::npos;
}

}  // namespace

DrillRunner::DrillRunner(DrillConfig drill, ExerciseConfig exercise, DrillOptions options)
    : drill_(std::move(drill)),
      exercise_(std::move(exercise)),
      options_(std::move(options)),
      sup_([this](const std::string& name, std::string_view line) {
        std::FILE*& f = logs_[name];
        if (f == nullptr) {
          f = std::fopen((exercise_.run_dir / (name + ".log")).c_str(), "a");
        }
        if (f != nullptr) {
          std::fprintf(f, "%.*s\n", static_cast<int>(line.size()), line.data());
          std::fflush(f);
        }
        const bool report = SanitizerReport(line);
        if (report) sanitizer_reports_.push_back(fmt::format("{}: {}", name, line));
        if (options_.echo_output || report || Notable(line)) Supervisor::PrintPrefixed(name, line);
      }) {
  std::error_code ec;
  std::filesystem::remove_all(exercise_.run_dir, ec);
  std::filesystem::create_directories(exercise_.run_dir);
  sup_.set_wake_fd(options_.wake_fd);
  carrier_url_ = options_.transport_override;
  if (exercise_.hosts.mode != HostsMode::kNone) {
    hosts_ = std::make_unique<HostNetwork>(exercise_);
    carrier_url_ = hosts_->CarrierUrl(carrier_url_.empty() ? exercise_.transport_url : carrier_url_,
                                      exercise_.run_dir);
    std::printf("[drill] hosts mode %s: every process on a host of its own, carrier %s\n",
                std::string(HostsModeName(exercise_.hosts.mode)).c_str(), carrier_url_.c_str());
    std::fflush(stdout);
  }
}

double DrillRunner::ElapsedS() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

bool DrillRunner::Expired() const { return ElapsedS() > drill_.deadline_s; }

std::vector<std::string> DrillRunner::Expand(const std::vector<std::string>& names) const {
  if (!names.empty()) return names;
  std::vector<std::string> all;
  for (const ProcessConfig* p : exercise_.Processes()) all.push_back(p->name);
  return all;
}

std::vector<std::string> DrillRunner::Live() const {
  std::vector<std::string> out;
  for (const ProcessConfig* p : exercise_.Processes()) {
    if (sup_.running(p->name)) out.push_back(p->name);
  }
  return out;
}

std::vector<std::string> DrillRunner::LiveNodes() const {
  std::vector<std::string> out;
  for (const ProcessConfig& n : exercise_.nodes) {
    if (sup_.running(n.name)) out.push_back(n.name);
  }
  return out;
}

std::vector<std::string> DrillRunner::Command(const std::string& name) const {
  std::vector<std::string> extra = {"--run-dir", exercise_.run_dir.string()};
  if (!carrier_url_.empty()) extra.insert(extra.end(), {"--transport", carrier_url_});
  std::vector<std::string> argv =
      ProcessCommand(exercise_, *exercise_.FindProcess(name), options_.programs, extra);
  return hosts_ ? hosts_->OnHost(name, std::move(argv)) : argv;
}

Result<ControlReply> DrillRunner::Call(const std::string& name, const std::string& line,
                                       int timeout_ms) {
  sup_.Poll(0);  // keep children's output moving
  return CallControl(exercise_.SocketPath(name), line, timeout_ms);
}

Result<StatusReport> DrillRunner::Status(const std::string& name) {
  Result<ControlReply> r = Call(name, "status");
  if (!r) return r.error();
  if (!r.value().ok) return Error{r.value().error};
  Result<StatusReport> status = StatusReport::Parse(r.value().body);
  if (status) {
    int64_t& seen = acked_[{name, incarnation_[name]}];
    seen = std::max(seen, status.value().acknowledged_change_seq);
  }
  return status;
}

void DrillRunner::StartProcess(const std::string& name) {
  // Nothing in run_dir is touched: a server reopens its database, a node its own files (such as
  // its feature-number reservation); a node's terrain is in memory only, so it starts without it.
  sup_.Start(name, Command(name));
  if (incarnation_[name]++ > 0) ++restarts_;
  stopped_.erase(name);
}

void DrillRunner::KillNow(const std::string& n) {
  const bool was_running = sup_.running(n);
  sup_.Signal(n, SIGKILL);
  if (hosts_) hosts_->KillHost(n);  // a host's processes die with it, escaped ones too
  kills_ += was_running ? 1 : 0;
  if (!sup_.WaitExit(n, 10000)) {
    Check("kill " + n, false, "still running");
  } else if (was_running) {
    // Only this kill may end it: an earlier exit is a crash the kill would hide.
    const int st = sup_.last_wait_status(n);
    if (!WIFSIGNALED(st) || WTERMSIG(st) != SIGKILL) {
      Check("kill " + n, false, "it had already " + DescribeWaitStatus(st));
    }
  }
  stopped_.insert(n);
}

void DrillRunner::StartAll() {
  std::vector<std::string> servers = {exercise_.server->name};  // dt_drill refuses none
  if (exercise_.standby) servers.push_back(exercise_.standby->name);
  for (const std::string& s : servers) StartProcess(s);
  dt::Status st = sup_.WaitReady(servers, static_cast<int>(drill_.ready_timeout_s * 1000));
  std::vector<std::string> all = servers;
  if (st) {
    for (const ProcessConfig& n : exercise_.nodes) {
      StartProcess(n.name);
      all.push_back(n.name);
    }
    st = sup_.WaitReady(all, static_cast<int>(drill_.ready_timeout_s * 1000));
  }
  Check("every process READY at start", st.ok(), st ? "" : st.error().message);
  if (!st) fatal_ = true;
}

void DrillRunner::RunAction(const DrillAction& a) {
  std::printf("[drill] %.1f s: %s\n", ElapsedS(), a.where.c_str());
  std::fflush(stdout);
  switch (a.kind) {
    case DrillActionKind::kRandomOps: {
      std::printf("[drill] random_ops: seed %llu, %d operations over %.0f s\n",
                  static_cast<unsigned long long>(a.seed), a.count, a.duration_s);
      std::fflush(stdout);
      Burst b{&a, ElapsedS(), 0, std::mt19937_64(a.seed)};
      bursts_.push_back(std::move(b));
      return;
    }
    case DrillActionKind::kChaos:
      StartChaos(a);
      return;
    case DrillActionKind::kKill:
      for (const std::string& n : a.targets) KillNow(n);
      return;
    case DrillActionKind::kStop:
      for (const std::string& n : a.targets) {
        sup_.Signal(n, SIGTERM);
        stopped_.insert(n);
        const bool ended = sup_.WaitExit(n, 15000);
        const int st = sup_.last_wait_status(n);
        Check("stop " + n, ended && WIFEXITED(st) && WEXITSTATUS(st) == 0,
              ended ? DescribeWaitStatus(st) : "still running");
      }
      return;
    case DrillActionKind::kRestart: {
      for (const std::string& n : a.targets) StartProcess(n);
      dt::Status st = sup_.WaitReady(a.targets, static_cast<int>(drill_.ready_timeout_s * 1000));
      Check(fmt::format("restart {} READY", fmt::join(a.targets, ", ")), st.ok(),
            st ? "" : st.error().message);
      return;
    }
    case DrillActionKind::kLoss:
      for (const std::string& n : Expand(a.targets)) {
        if (!sup_.running(n)) continue;
        Result<ControlReply> r = Call(n, fmt::format("loss {}", a.drop_probability));
        if (!r || !r.value().ok)
          Check("loss on " + n, false, r ? r.value().error : r.error().message);
      }
      return;
    case DrillActionKind::kPartition: {
      if (hosts_) {  // a real link cut (docs/deploy.md)
        try {
          hosts_->Cut(a.targets, a.from);
        } catch (const std::exception& e) {
          Check("partition", false, e.what());
        }
        return;
      }
      auto addresses = [&](const std::vector<std::string>& names) {
        std::string out;
        for (const std::string& n : names) {
          out += ' ';  // appended apart: GCC 12 -O3 warns falsely on " " + string
          out += exercise_.FindProcess(n)->address.ToString();
        }
        return out;
      };
      for (const auto& [side, other] :
           {std::pair{a.targets, a.from}, std::pair{a.from, a.targets}}) {
        for (const std::string& n : side) {
          if (!sup_.running(n)) continue;
          Result<ControlReply> r = Call(n, "partition" + addresses(other));
          if (!r || !r.value().ok)
            Check("partition " + n, false, r ? r.value().error : r.error().message);
        }
      }
      return;
    }
    case DrillActionKind::kHeal:
      HealLinks();
      for (const std::string& n : Live()) (void)Call(n, "heal");
      return;
    case DrillActionKind::kCommand: {
      std::map<std::string, std::string> names = kept_ids_;
      names["run_dir"] = exercise_.run_dir.string();
      const std::string line = WithNames(a.line, names);
      for (const std::string& n : Expand(a.targets)) {
        Result<ControlReply> r = Call(n, line, kOpTimeoutMs);
        Check(fmt::format("{} on {}", line, n), r && r.value().ok,
              r ? r.value().error : r.error().message);
        // A create's IDs count like those of random operations (no ID issued twice, etc.).
        if (r && r.value().ok) RecordAccepted(n, line, r.value());
        if (!r) RecordUnanswered(n, line, r.error().message);
        if (!a.as.empty() && r && r.value().ok) {
          // The first ID of the reply, for the later lines that name it.
          const std::string first = r.value().body.substr(0, r.value().body.find('\n'));
          if (ParseFeatureId(first)) {
            kept_ids_[a.as] = first;
          } else {
            Check(fmt::format("{} on {} gives an ID to keep as {}", line, n, a.as), false,
                  r.value().body);
          }
        }
      }
      return;
    }
    case DrillActionKind::kVehiclesSeen:
      VehiclesSeen(a);
      return;
    case DrillActionKind::kVehicleReaches:
      VehicleReaches(a);
      return;
    case DrillActionKind::kDigest:
      DigestMark(a);
      return;
    case DrillActionKind::kSampleVehicles: {
      Sampling v;
      v.action = &a;
      v.start_s = v.next_s = ElapsedS();
      samplings_.push_back(std::move(v));
      return;
    }
  }
}

void DrillRunner::HealLinks() {
  if (!hosts_) return;
  try {
    hosts_->Heal();
  } catch (const std::exception& e) {
    Check("heal", false, e.what());
  }
}

bool DrillRunner::Converge(std::string& detail) {
  HealLinks();
  for (const std::string& n : Live()) {
    (void)Call(n, "loss 0");
    (void)Call(n, "heal");
  }
  const double until_s = std::min(ElapsedS() + drill_.settle_s, drill_.deadline_s);
  for (;;) {
    if (AgreeOnce(detail)) return true;
    if (ElapsedS() >= until_s) return false;
    if (sup_.Poll(250)) return false;  // interrupted
  }
}

bool DrillRunner::AgreeOnce(std::string& detail) {
  std::map<std::string, std::string> digests;
  bool all_caught_up = true;
  bool all_acked = true;
  for (const std::string& n : Live()) {
    const Result<StatusReport> st = Status(n);
    if (!st) {
      all_caught_up = false;
      continue;
    }
    digests[n] = st.value().digest;
    dropped_[n] = st.value().fault_dropped;
    all_caught_up &= st.value().caught_up;
    if (st.value().role == NodeRole::kNode) {
      all_acked &= st.value().acknowledged_change_seq == st.value().own_change_seq;
    }
  }
  std::set<std::string> distinct;
  for (const auto& [n, d] : digests) distinct.insert(d);
  digests_equal_ = distinct.size() == 1;
  last_digests_ = digests;
  detail.clear();
  for (const auto& [n, d] : digests) detail += fmt::format("\n    {:10} {}", n, d);
  if (distinct.size() == 1 && all_caught_up && all_acked) return true;
  detail += fmt::format("\n    caught_up everywhere: {}, every change acknowledged: {}",
                        all_caught_up, all_acked);
  return false;
}

std::set<FeatureId> DrillRunner::Features(const std::string& name) {
  std::set<FeatureId> out;
  Result<ControlReply> r = Call(name, "features", 10000);
  if (r && r.value().ok) {
    std::istringstream in(r.value().body);
    for (std::string l; std::getline(in, l);) {
      if (auto id = ParseFeatureId(l)) out.insert(id.value());
    }
  }
  return out;
}

void DrillRunner::ReportDivergence() {
  const std::vector<std::string> live = Live();
  if (live.size() < 2) return;
  const std::set<FeatureId> first = Features(live.front());
  auto some = [](const std::vector<std::string>& ids) {
    const size_t shown = std::min<size_t>(ids.size(), 10);
    return fmt::format("{}{}", fmt::join(ids.begin(), ids.begin() + static_cast<long>(shown), ", "),
                       ids.size() > shown ? fmt::format(" and {} more", ids.size() - shown) : "");
  };
  for (size_t i = 1; i < live.size(); ++i) {
    if (last_digests_[live[i]] == last_digests_[live.front()]) continue;
    const std::set<FeatureId> other = Features(live[i]);
    std::vector<std::string> extra, missing;
    for (const FeatureId& id : other) {
      if (first.count(id) == 0) extra.push_back(id.ToString());
    }
    for (const FeatureId& id : first) {
      if (other.count(id) == 0) missing.push_back(id.ToString());
    }
    if (extra.empty() && missing.empty()) {
      report_.push_back(
          fmt::format("  {} holds the live feature IDs {} holds ({}), with other "
                      "parameters",
                      live[i], live.front(), other.size()));
      continue;
    }
    report_.push_back(
        fmt::format("  {} beside {}: {} live features only on {}{}{}, {} only on {}{}{}", live[i],
                    live.front(), extra.size(), live[i], extra.empty() ? "" : ": ", some(extra),
                    missing.size(), live.front(), missing.empty() ? "" : ": ", some(missing)));
  }
}

void DrillRunner::CheckFeatures() {
  std::vector<std::string> reused;
  for (const FeatureId& id : reused_ids_) reused.push_back(id.ToString());
  Check("no feature ID issued twice", reused_ids_.empty(),
        reused_ids_.empty() ? fmt::format("{} IDs issued", issued_ids_.size())
                            : fmt::format("reused: {}", fmt::join(reused, ", ")));
  // Acknowledged = at or below the highest acknowledged sequence the issuing incarnation of
  // the node reported.
  std::set<FeatureId> must_live, must_be_gone;
  int unacked_creates = 0, unacked_destroys = 0;
  for (const Op& op : ops_) {
    const auto ack = acked_.find({op.node, op.incarnation});
    const bool acked = op.seq >= 0 && ack != acked_.end() && op.seq <= ack->second;
    acked_ops_ += acked ? 1 : 0;
    if (op.kind == OpKind::kCreate) {
      if (acked)
        must_live.insert(op.id);
      else
        ++unacked_creates;
    } else if (op.kind == OpKind::kDestroy) {
      must_live.erase(op.id);
      if (acked)
        must_be_gone.insert(op.id);
      else
        ++unacked_destroys;
    }
  }
  for (const FeatureId& id : must_be_gone) must_live.erase(id);
  for (const FeatureId& id : maybe_gone_) must_live.erase(id);
  const std::vector<std::string> live = Live();
  const std::set<FeatureId> present = live.empty() ? std::set<FeatureId>{} : Features(live.front());
  const long expected = static_cast<long>(alive_.size());
  // Only IDs the drill issued count: not features of scenarios, nor of creates it had no reply to.
  long have = 0;
  for (const FeatureId& id : present) have += issued_ids_.count(id) != 0 ? 1 : 0;
  long maybe_gone = 0;
  for (const FeatureId& id : maybe_gone_) maybe_gone += alive_.count(id) != 0 ? 1 : 0;
  report_.push_back(fmt::format("  {} features live in all ({} not issued to the drill)",
                                present.size(), static_cast<long>(present.size()) - have));
  if (ops_unanswered_ > 0) {
    report_.push_back(fmt::format(
        "  {} commands unanswered within {} s (outcome unknown: what they destroy is left out "
        "of the checks), first: {}",
        ops_unanswered_, kOpTimeoutMs / 1000, fmt::join(unanswered_, "; ")));
  }
  report_.push_back(fmt::format("  slowest reply to a random operation: {:.2f} s ({})",
                                slowest_reply_s_,
                                slowest_reply_.empty() ? "none" : slowest_reply_));
  Check("expected feature count (of the drill's own operations)",
        have >= expected - unacked_creates - maybe_gone && have <= expected + unacked_destroys,
        fmt::format("{} live, {} expected ({} unacknowledged creates, {} destroys may be lost, "
                    "{} maybe destroyed; {} operations ran, {} refused, {} unanswered)",
                    have, expected, unacked_creates, unacked_destroys, maybe_gone, ops_.size(),
                    ops_failed_, ops_unanswered_));
  std::vector<std::string> lost;
  for (const FeatureId& id : must_live) {
    if (!present.count(id)) lost.push_back(id.ToString());
  }
  for (const FeatureId& id : must_be_gone) {
    if (present.count(id)) lost.push_back(id.ToString() + " (destroyed, came back)");
  }
  lost_count_ = lost.size();
  Check("nothing acknowledged lost", lost.empty(),
        lost.empty() ? fmt::format("{} acknowledged live features checked", must_live.size())
                     : fmt::format("{}", fmt::join(lost, ", ")));
}

void DrillRunner::Check(const std::string& what, bool ok, const std::string& detail) {
  const std::string line =
      fmt::format("  [{}] {}{}{}", ok ? "PASS" : "FAIL", what, detail.empty() ? "" : ": ", detail);
  report_.push_back(line);
  if (!ok) failures_.push_back(what);
  std::printf("[drill] %s\n", line.c_str());
  std::fflush(stdout);
}

void DrillRunner::Renders() {
  std::vector<Image> images;
  std::vector<std::string> labels;
  for (const std::string& n : LiveNodes()) {
    const std::filesystem::path png = exercise_.run_dir / ("render-" + n + ".png");
    Result<ControlReply> r = Call(n, "render " + png.string(), 60000);
    if (!r || !r.value().ok) {
      report_.push_back(
          fmt::format("  render of {} failed: {}", n, r ? r.value().error : r.error().message));
      continue;
    }
    Result<Image> img = ReadPng(png.string());
    if (img) {
      images.push_back(std::move(img).value());
      labels.push_back(n);
    }
  }
  if (images.empty()) return;
  const std::filesystem::path montage = exercise_.run_dir / "montage.png";
  if (WritePng(Montage(images, labels), montage.string())) {
    report_.push_back("  renders: " + (exercise_.run_dir / "render-*.png").string() + ", " +
                      montage.string());
  }
}

int DrillRunner::Run() {
  start_ = std::chrono::steady_clock::now();
  std::printf(
      "[drill] %s: exercise %s over %s, run dir %s\n", drill_.name.c_str(), exercise_.name.c_str(),
      (options_.transport_override.empty() ? exercise_.transport_url : options_.transport_override)
          .c_str(),
      exercise_.run_dir.c_str());
  std::fflush(stdout);
  try {
    StartAll();
    size_t next = 0;
    bool interrupted = false;
    while (!fatal_ && !interrupted) {
      const double now_s = ElapsedS();
      while (next < drill_.actions.size() && drill_.actions[next].at_s <= now_s) {
        RunAction(drill_.actions[next++]);
      }
      bool busy = false;
      double next_due_s = 1e300;
      for (Burst& b : bursts_) {
        const DrillAction& a = *b.action;
        while (b.issued < a.count && b.start_s + a.duration_s * b.issued / a.count <= ElapsedS()) {
          RandomOp(b);
        }
        if (b.issued < a.count) {
          busy = true;
          next_due_s = std::min(next_due_s, b.start_s + a.duration_s * b.issued / a.count);
        }
      }
      for (Chaos& c : chaos_) busy |= ChaosStep(c, next_due_s);
      for (Sampling& v : samplings_) busy |= SampleStep(v, next_due_s);
      if (next >= drill_.actions.size() && !busy) break;
      if (Expired()) {
        Check("timeline within the deadline", false,
              fmt::format("{} s passed with the timeline unfinished", drill_.deadline_s));
        fatal_ = true;
        break;
      }
      if (next < drill_.actions.size())
        next_due_s = std::min(next_due_s, drill_.actions[next].at_s);
      const int wait_ms =
          static_cast<int>(std::clamp((next_due_s - ElapsedS()) * 1000.0, 0.0, 250.0));
      interrupted = sup_.Poll(wait_ms);
    }
    if (interrupted) Check("not interrupted", false, "stopped by a signal");

    if (!fatal_ && !interrupted) {
      std::string detail;
      const double converge_start_s = ElapsedS();
      const bool converged = Converge(detail);
      Check(fmt::format("equal digests on every live process, all caught up and acknowledged "
                        "({:.1f} s after the timeline)",
                        ElapsedS() - converge_start_s),
            converged, detail);
      if (!digests_equal_) ReportDivergence();
      uint64_t dropped = 0;
      for (const auto& [n, d] : dropped_) dropped += d;
      report_.push_back(
          fmt::format("  {} messages dropped by fault injection (live processes)", dropped));
      CheckFeatures();
      const double renders_start_s = ElapsedS();
      Renders();
      report_.push_back(fmt::format("  renders took {:.1f} s", ElapsedS() - renders_start_s));
    }
  } catch (const std::exception& e) {
    Check("drill ran", false, e.what());
  }
  const std::vector<std::string> still = Live();
  // A child that ended by itself (a crash, a sanitizer's abort) is a failure even when the
  // others converged without it.
  for (const std::string& n : sup_.names()) {
    if (sup_.running(n) || stopped_.count(n) != 0) continue;
    Check(n + " runs until the drill stops it", false,
          DescribeWaitStatus(sup_.last_wait_status(n)));
  }
  sup_.StopAll(15000);
  for (const std::string& n : still) {
    const int st = sup_.last_wait_status(n);
    Check(n + " stops cleanly", WIFEXITED(st) && WEXITSTATUS(st) == 0, DescribeWaitStatus(st));
  }
  Check("no sanitizer report in any process's output", sanitizer_reports_.empty(),
        sanitizer_reports_.empty() ? ""
                                   : fmt::format("{} reports, first {}", sanitizer_reports_.size(),
                                                 sanitizer_reports_.front()));
  for (Sampling& v : samplings_) {
    if (v.csv != nullptr) std::fclose(v.csv);  // a drill cut short
    v.csv = nullptr;
  }
  for (auto& [n, f] : logs_) {
    if (f != nullptr) std::fclose(f);
  }
  logs_.clear();
  std::printf("\n== drill %s: %s in %.1f s ==\n", drill_.name.c_str(),
              failures_.empty() ? "PASS" : "FAIL", ElapsedS());
  for (const std::string& l : report_) std::printf("%s\n", l.c_str());
  // One line for scripts (scripts/campaigns.sh).
  std::printf(
      "[drill] summary result=%s kills=%d restarts=%d ops=%zu acknowledged=%zu refused=%d "
      "unanswered=%d lost=%zu ids_twice=%zu digests_equal=%s\n",
      failures_.empty() ? "PASS" : "FAIL", kills_, restarts_, ops_.size(), acked_ops_, ops_failed_,
      ops_unanswered_, lost_count_, reused_ids_.size(), digests_equal_ ? "yes" : "no");
  std::fflush(stdout);
  return failures_.empty() ? 0 : 1;
}

}  // namespace dt

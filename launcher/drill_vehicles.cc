// The drill's vehicle actions: vehicles_seen, sample_vehicles and vehicle_reaches
// (docs/launcher.md "Vehicle actions"), read from the nodes' `vehicles` replies.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "launcher/drill_runner.h"

namespace dt {

std::vector<std::string> DrillRunner::VehicleTargets(const DrillAction& a) const {
  if (!a.targets.empty()) return a.targets;
  std::vector<std::string> out;
  for (const ProcessConfig& n : exercise_.nodes) {
    // vehicles_seen watches the owner's vehicles from the other nodes.
    if (a.kind == DrillActionKind::kVehiclesSeen && n.name == a.owner) continue;
    out.push_back(n.name);
  }
  return out;
}

Result<std::vector<ListedVehicle>> DrillRunner::Vehicles(const std::string& node) {
  Result<ControlReply> r = Call(node, "vehicles");
  if (!r) return r.error();
  if (!r.value().ok) return Error{fmt::format("{}: {}", node, r.value().error)};
  Result<std::vector<ListedVehicle>> v = ParseVehicleListing(r.value().body);
  if (!v) return Error{fmt::format("{}: {}", node, v.error().message)};
  return v;
}

void DrillRunner::VehiclesSeen(const DrillAction& a) {
  const std::string owner_address = exercise_.FindProcess(a.owner)->address.ToString();
  const std::vector<std::string> targets = VehicleTargets(a);
  const std::string what = fmt::format("{} {} {}'s vehicles within {} s", fmt::join(targets, ", "),
                                       targets.size() == 1 ? (a.seen ? "holds" : "no longer holds")
                                                           : (a.seen ? "hold" : "no longer hold"),
                                       a.owner, a.within_s);
  const double start_s = ElapsedS();
  std::map<std::string, double> done_s;  // target -> when it first held (or lost) them
  std::string last_problem;
  for (;;) {
    const double t_s = ElapsedS() - start_s;
    // What the owner holds itself (seen): every one of its vehicles must be held remote.
    std::set<std::string> wanted;
    bool owner_known = !a.seen;
    if (a.seen) {
      Result<std::vector<ListedVehicle>> own =
          sup_.running(a.owner)
              ? Vehicles(a.owner)
              : Result<std::vector<ListedVehicle>>(Error{a.owner + " is not running"});
      if (own) {
        for (const ListedVehicle& v : own.value()) {
          if (v.local) wanted.insert(v.entity);
        }
        owner_known = !wanted.empty();
        if (wanted.empty()) last_problem = a.owner + " has no vehicles of its own";
      } else {
        last_problem = own.error().message;
      }
    }
    for (const std::string& n : targets) {
      if (done_s.count(n) != 0 || !owner_known) continue;
      if (!sup_.running(n)) {
        last_problem = n + " is not running";
        continue;
      }
      Result<std::vector<ListedVehicle>> seen = Vehicles(n);
      if (!seen) {
        last_problem = seen.error().message;
        continue;
      }
      std::set<std::string> held;
      for (const ListedVehicle& v : seen.value()) {
        if (!v.local && v.owner == owner_address) held.insert(v.entity);
      }
      const bool ok = a.seen ? std::includes(held.begin(), held.end(), wanted.begin(), wanted.end())
                             : held.empty();
      if (ok) {
        done_s[n] = t_s;
      } else {
        last_problem = fmt::format("{} holds {} of {}'s vehicles ({})", n, held.size(), a.owner,
                                   fmt::join(held, ", "));
      }
    }
    if (done_s.size() == targets.size()) break;
    if (t_s > a.within_s || Expired()) {
      Check(what, false, fmt::format("not after {:.1f} s: {}", t_s, last_problem));
      return;
    }
    if (PollBeside(100)) {
      Check(what, false, "interrupted");
      return;
    }
  }
  std::vector<std::string> times;
  bool too_soon = false;
  for (const std::string& n : targets) {
    times.push_back(fmt::format("{} after {:.1f} s", n, done_s[n]));
    too_soon |= done_s[n] < a.not_before_s;
  }
  Check(a.not_before_s > 0.0 ? fmt::format("{}, not before {} s", what, a.not_before_s) : what,
        !too_soon, fmt::format("{}", fmt::join(times, ", ")));
}

void DrillRunner::VehicleReaches(const DrillAction& a) {
  std::string box;  // the bounds given, as "x >= 70 m, z 30..50 m"
  for (const auto& [axis, lo, hi] :
       {std::tuple{"x", a.x_min_m, a.x_max_m}, std::tuple{"z", a.z_min_m, a.z_max_m}}) {
    const bool has_lo = lo > -1e299, has_hi = hi < 1e299;
    if (!has_lo && !has_hi) continue;
    box += box.empty() ? "" : ", ";
    box += has_lo && has_hi ? fmt::format("{} {}..{} m", axis, lo, hi)
           : has_lo         ? fmt::format("{} >= {} m", axis, lo)
                            : fmt::format("{} <= {} m", axis, hi);
  }
  const std::string what =
      fmt::format("{}'s vehicle {} alive at {} within {} s", a.owner, a.vehicle, box, a.within_s);
  const double start_s = ElapsedS();
  std::string last = "no reply yet";
  for (;;) {
    const double t_s = ElapsedS() - start_s;
    Result<std::vector<ListedVehicle>> listed =
        sup_.running(a.owner)
            ? Vehicles(a.owner)
            : Result<std::vector<ListedVehicle>>(Error{a.owner + " is not running"});
    if (listed) {
      const auto it = std::find_if(listed.value().begin(), listed.value().end(),
                                   [&](const ListedVehicle& v) { return v.index == a.vehicle; });
      if (it == listed.value().end()) {
        last = fmt::format("{} has no vehicle {}", a.owner, a.vehicle);
      } else {
        last = fmt::format(
            "{} {} at x {:.1f} z {:.1f} y {:.2f}, heading {:.0f}, pitch {:.1f}, "
            "roll {:.1f} degrees, {:.1f} m/s, alive {}",
            it->type, it->entity, it->x_m, it->z_m, it->y_m, it->heading_deg, it->pitch_deg,
            it->roll_deg, it->speed_mps, it->alive ? 1 : 0);
        if (!it->alive) break;  // it will not get there
        if (it->x_m >= a.x_min_m && it->x_m <= a.x_max_m && it->z_m >= a.z_min_m &&
            it->z_m <= a.z_max_m) {
          Check(what, true, fmt::format("after {:.1f} s: {}", t_s, last));
          return;
        }
      }
    } else {
      last = listed.error().message;
    }
    if (t_s > a.within_s || Expired()) break;
    if (PollBeside(100)) {
      Check(what, false, "interrupted");
      return;
    }
  }
  Check(what, false, fmt::format("not after {:.1f} s: {}", ElapsedS() - start_s, last));
}

bool DrillRunner::PollBeside(int timeout_ms) {
  // A sampling started before a blocking action goes on while it waits: it is meant to see what
  // the vehicles do meanwhile (a tank crossing a crater while the drill waits for another).
  double next_due_s = 1e300;
  for (Sampling& v : samplings_) (void)SampleStep(v, next_due_s);
  const double wait_s = std::min(next_due_s - ElapsedS(), timeout_ms / 1000.0);
  return sup_.Poll(static_cast<int>(std::clamp(wait_s, 0.0, timeout_ms / 1000.0) * 1000.0));
}

bool DrillRunner::SampleStep(Sampling& s, double& next_due_s) {
  const DrillAction& a = *s.action;
  if (s.rounds < 0) return false;  // finished
  const double end_s = s.start_s + a.duration_s;
  if (ElapsedS() >= s.next_s && s.next_s < end_s) {
    SampleRound(s);
    s.next_s = std::max(s.next_s + a.period_s, ElapsedS());
  }
  if (s.next_s >= end_s) {
    FinishSampling(s);
    s.rounds = -1;
    return false;
  }
  next_due_s = std::min(next_due_s, s.next_s);
  return true;
}

void DrillRunner::SampleRound(Sampling& s) {
  const DrillAction& a = *s.action;
  const std::string owner_address =
      a.owner.empty() ? "" : exercise_.FindProcess(a.owner)->address.ToString();
  auto note_error = [&](const std::string& e) {
    if (s.errors.size() < 3) s.errors.push_back(e);
  };
  ++s.rounds;
  if (s.rounds == 1) {
    // Every sample, for a look at how errors come and go (docs/launcher.md).
    const std::filesystem::path path =
        exercise_.run_dir / fmt::format("vehicle-samples-{}.csv", &s - samplings_.data() + 1);
    s.csv = std::fopen(path.c_str(), "w");
    if (s.csv != nullptr)
      std::fprintf(s.csv, "t_s,node,entity,error_m,age_s,owner_speed_mps,tilt_deg\n");
  }
  // Every live node once, in turn: the owners' truth (their local lines), then the remote copies
  // on the targets. The replies are milliseconds apart (docs/launcher.md says what that costs).
  std::map<std::string, ListedVehicle> truth;  // entity -> the owner's own pose
  std::map<std::string, std::vector<ListedVehicle>> remote;
  const std::vector<std::string> targets = VehicleTargets(a);
  for (const std::string& n : LiveNodes()) {
    Result<std::vector<ListedVehicle>> v = Vehicles(n);
    if (!v) {
      note_error(v.error().message);
      continue;
    }
    const bool target = std::find(targets.begin(), targets.end(), n) != targets.end();
    for (const ListedVehicle& l : v.value()) {
      if (!owner_address.empty() && l.owner != owner_address) continue;
      if (l.local) {
        truth[l.entity] = l;
      } else if (target) {
        remote[n].push_back(l);
      }
    }
  }
  const double t_s = ElapsedS() - s.start_s;
  for (const auto& [n, list] : remote) {
    for (const ListedVehicle& r : list) {
      if (TiltDeg(r) > s.max_tilt_deg) {
        s.max_tilt_deg = TiltDeg(r);
        s.max_tilt_where = fmt::format(
            "{} on {} at {:.1f} s: pitch {:.1f}, roll {:.1f} degrees at x {:.1f} z {:.1f}",
            r.entity, n, t_s, r.pitch_deg, r.roll_deg, r.x_m, r.z_m);
      }
      const auto it = truth.find(r.entity);
      if (it == truth.end()) continue;  // its owner did not answer (or is down)
      // Horizontal: the receiver settles y on its own terrain (docs/vehicles.md).
      const double error_m = std::hypot(r.x_m - it->second.x_m, r.z_m - it->second.z_m);
      auto& [within, all] = s.error_samples[n];
      ++all;
      within += error_m <= a.error_m ? 1 : 0;
      s.worst_error_m = std::max(s.worst_error_m, error_m);
      if (s.csv != nullptr) {
        std::fprintf(s.csv, "%.2f,%s,%s,%.3f,%.2f,%.2f,%.2f\n", t_s, n.c_str(), r.entity.c_str(),
                     error_m, r.age_s, it->second.speed_mps, TiltDeg(r));
      }
    }
  }
}

void DrillRunner::FinishSampling(Sampling& s) {
  const DrillAction& a = *s.action;
  if (s.csv != nullptr) std::fclose(s.csv);
  s.csv = nullptr;
  const std::string whose = a.owner.empty() ? "remote vehicles" : a.owner + "'s vehicles";
  const std::string errors =
      s.errors.empty() ? "" : fmt::format("; failed replies: {}", fmt::join(s.errors, "; "));
  if (a.min_tilt_deg >= 0.0) {
    Check(fmt::format("{} tilt beyond {} degrees on {}", whose, a.min_tilt_deg,
                      fmt::join(VehicleTargets(a), ", ")),
          s.max_tilt_deg >= a.min_tilt_deg,
          s.max_tilt_deg < 0.0 ? fmt::format("none seen in {} rounds{}", s.rounds, errors)
                               : fmt::format("max tilt {:.1f} degrees ({}), {} rounds{}",
                                             s.max_tilt_deg, s.max_tilt_where, s.rounds, errors));
  }
  if (a.min_fraction >= 0.0) {
    std::vector<std::string> per_node;
    bool ok = true;
    int within_all = 0, all_all = 0;
    for (const std::string& n : VehicleTargets(a)) {
      const auto [within, all] = s.error_samples[n];
      within_all += within;
      all_all += all;
      const double fraction = all > 0 ? static_cast<double>(within) / all : 0.0;
      ok &= all > 0;  // every target held some vehicle with a known truth
      per_node.push_back(fmt::format("{} {:.3f} ({}/{})", n, fraction, within, all));
    }
    const double fraction_all = all_all > 0 ? static_cast<double>(within_all) / all_all : 0.0;
    Check(fmt::format("{} within {} m of their owner's truth in at least {} of the samples", whose,
                      a.error_m, a.min_fraction),
          ok && fraction_all >= a.min_fraction,
          fmt::format("{:.3f} ({}/{}); per node {}; worst {:.2f} m, {} rounds{}", fraction_all,
                      within_all, all_all, fmt::join(per_node, ", "), s.worst_error_m, s.rounds,
                      errors));
  }
}

}  // namespace dt

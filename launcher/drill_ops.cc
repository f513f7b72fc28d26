// DrillRunner's operations: random creates, updates, destroys and breaches, and the drill's model
// of the features it made (docs/launcher.md "Drill files").
#include <algorithm>
#include <chrono>
#include <iterator>
#include <sstream>

#include <fmt/format.h>

#include "launcher/drill_runner.h"
#include "launcher/seeded_draws.h"
#include "runtime/control_command.h"
#include "terrain/berm_operations.h"

namespace dt {
namespace {

template <typename C>
auto Pick(std::mt19937_64& rng, const C& c) {
  auto it = c.begin();
  std::advance(it, static_cast<long>(rng() % c.size()));
  return it;
}

}  // namespace

void DrillRunner::NoteIssued(const FeatureId& id) {
  if (!issued_ids_.insert(id).second) reused_ids_.push_back(id);
}

void DrillRunner::RandomOp(Burst& b) {
  const DrillAction& a = *b.action;
  std::vector<std::string> candidates;
  // Ready, not merely running: a restarted node refuses commands until it has signed on.
  for (const std::string& n : a.targets.empty() ? LiveNodes() : a.targets) {
    if (sup_.running(n) && sup_.ready(n)) candidates.push_back(n);
  }
  ++b.issued;
  if (candidates.empty()) return;
  const std::string node = candidates[b.rng() % candidates.size()];
  // A coordinate along an axis of size_m, margin_m (at most a quarter of it) from either edge.
  auto coordinate = [&](double margin_m, double size_m) {
    margin_m = std::min(margin_m, size_m / 4.0);
    return SeededUniform(b.rng, margin_m, size_m - margin_m);
  };
  auto x_coordinate = [&](double margin_m) {
    return coordinate(margin_m, exercise_.terrain_size_x_m());
  };
  auto z_coordinate = [&](double margin_m) {
    return coordinate(margin_m, exercise_.terrain_size_z_m());
  };
  // Creates 55 % (a third of them berms), updates 20 %, destroys 15 %, breaches 10 % (of a berm
  // the drill made; a create when it knows none).
  const int dice = static_cast<int>(b.rng() % 20);
  std::string line;
  if (dice < 11 || alive_.empty() || (dice >= 18 && berms_.empty())) {
    if (b.rng() % 3 == 0) {
      line = fmt::format("berm {:.2f} {:.2f} {:.1f} {:.2f} {:.2f} {:.2f}", x_coordinate(60.0),
                         z_coordinate(60.0), SeededUniform(b.rng, 0.0, 360.0),
                         SeededUniform(b.rng, 20.0, 40.0), SeededUniform(b.rng, 3.0, 6.0),
                         SeededUniform(b.rng, 1.0, 3.0));
    } else {
      const double x_m = x_coordinate(20.0);
      const double z_m = z_coordinate(20.0);
      line = fmt::format("crater {:.2f} {:.2f} {:.2f}", x_m, z_m, SeededUniform(b.rng, 2.0, 8.0));
    }
  } else if (dice < 18) {
    const FeatureId id = *Pick(b.rng, alive_);
    if (dice < 15) {
      const bool berm = berms_.count(id) != 0;
      line = fmt::format("update {} {}={:.2f}", id.ToString(), berm ? "height_m" : "radius_m",
                         berm ? SeededUniform(b.rng, 1.0, 3.0) : SeededUniform(b.rng, 2.0, 8.0));
    } else {
      line = "destroy " + id.ToString();
    }
  } else {
    const auto it = Pick(b.rng, berms_);
    const double length_m = it->second.length_m[0];
    const double gap_width_m = SeededUniform(b.rng, 2.0, 5.0);
    line = fmt::format("breach {} {:.2f} {:.2f}", it->first.ToString(),
                       SeededUniform(b.rng, 0.2, 0.6) * length_m, gap_width_m);
  }
  const auto sent = std::chrono::steady_clock::now();
  Result<ControlReply> r = Call(node, line, kOpTimeoutMs);
  const double reply_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  if (reply_s > slowest_reply_s_) {
    slowest_reply_s_ = reply_s;
    slowest_reply_ = fmt::format("\"{}\" on {}", line, node);
  }
  if (!r) {
    RecordUnanswered(node, line, r.error().message);
  } else if (!r.value().ok) {
    ++ops_failed_;  // a feature another node destroyed, a full window: not an error
  } else {
    RecordAccepted(node, line, r.value());
  }
}

void DrillRunner::RecordUnanswered(const std::string& node, const std::string& line,
                                   const std::string& error) {
  // The node may still carry it out (it did, when a blocking send held it past the timeout):
  // what it destroys may be gone, and what it creates has an ID the drill never learns.
  ++ops_unanswered_;
  if (unanswered_.size() < 5)
    unanswered_.push_back(fmt::format("\"{}\" on {}: {}", line, node, error));
  Result<ControlCommand> c = ParseControlCommand(line);
  if (c && (c.value().verb == ControlVerb::kDestroy || c.value().verb == ControlVerb::kBreach)) {
    maybe_gone_.insert(c.value().target);
  }
}

void DrillRunner::RecordAccepted(const std::string& node, const std::string& line,
                                 const ControlReply& reply) {
  Result<ControlCommand> parsed = ParseControlCommand(line);
  if (!parsed) return;  // the node accepted it, so it is no feature command the drill knows
  const ControlCommand& c = parsed.value();
  if (c.verb != ControlVerb::kCreate && c.verb != ControlVerb::kUpdate &&
      c.verb != ControlVerb::kDestroy && c.verb != ControlVerb::kBreach) {
    return;  // not a change of a feature (drive, spawn: its reply is a vehicle index)
  }
  std::vector<FeatureId> replied;
  std::istringstream in(reply.body);
  for (std::string l; std::getline(in, l);) {
    if (l.empty()) continue;
    Result<FeatureId> id = ParseFeatureId(l);
    if (!id) {
      Check(fmt::format("reply to \"{}\" on {}", line, node), false, reply.body);
      return;
    }
    replied.push_back(id.value());
  }
  std::vector<Op> made;
  switch (c.verb) {
    case ControlVerb::kCreate:
      if (replied.size() != 1) {
        Check(fmt::format("reply to \"{}\" on {}", line, node), false, reply.body);
        return;
      }
      made.push_back({node, 0, OpKind::kCreate, replied[0], -1});
      if (c.params.type == FeatureType::kBerm) berms_[replied[0]] = c.params;
      break;
    case ControlVerb::kUpdate:
      made.push_back({node, 0, OpKind::kUpdate, c.target, -1});
      break;
    case ControlVerb::kDestroy:
      made.push_back({node, 0, OpKind::kDestroy, c.target, -1});
      break;
    case ControlVerb::kBreach: {
      // One Destruct, then a Construct per piece, the pieces' IDs in the reply.
      made.push_back({node, 0, OpKind::kDestroy, c.target, -1});
      std::vector<FeatureParams> pieces;
      if (auto berm = berms_.find(c.target); berm != berms_.end()) {
        auto p = BreachBerm(berm->second, c.gap_start_m + c.gap_width_m / 2.0, c.gap_width_m);
        if (p && p.value().size() == replied.size()) pieces = p.value();
      }
      for (size_t i = 0; i < replied.size(); ++i) {
        made.push_back({node, 0, OpKind::kCreate, replied[i], -1});
        if (!pieces.empty()) berms_[replied[i]] = pieces[i];
      }
      break;
    }
    default:
      return;  // not a change of a feature
  }
  for (const Op& op : made) {
    if (op.kind == OpKind::kCreate) {
      NoteIssued(op.id);
      alive_.insert(op.id);
    } else if (op.kind == OpKind::kDestroy) {
      alive_.erase(op.id);
      berms_.erase(op.id);
    }
  }
  // Every change of the command is at or below the node's sequence now: counting all of them as
  // acknowledged only once that sequence is errs toward "not acknowledged", never the other way.
  const Result<StatusReport> st = Status(node);
  const int64_t seq = st ? st.value().own_change_seq : -1;
  for (Op& op : made) {
    op.seq = seq;
    op.incarnation = incarnation_[node];
    ops_.push_back(op);
  }
}

}  // namespace dt

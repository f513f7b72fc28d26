// The rules for what is believed: membership, roles and clock bounds a received PDU must meet
// (docs/protocol.md, "Rules for what is believed").
#include <fmt/format.h>

#include "engine/replica.h"
#include "log/log.h"

namespace dt {

NodeRole Replica::RoleOf(NodeAddress a, NodeRole claimed) const {
  if (config_.members.empty()) return claimed;
  auto it = config_.members.find(a);
  return it == config_.members.end() ? claimed : it->second;
}

void Replica::Refused(uint64_t& counter, const std::string& what) {
  ++counter;
  ++refusals_since_log_;
  // One line a second at most: a hostile or broken peer must not flood the log.
  if (last_refusal_log_ms_ < 0 || now_ms_ - last_refusal_log_ms_ >= 1000) {
    DT_LOG_WARN("replica {}: refused {} ({} refused since the last such line)",
                config_.address.ToString(), what, refusals_since_log_);
    last_refusal_log_ms_ = now_ms_;
    refusals_since_log_ = 0;
  }
}

bool Replica::Admits(NodeAddress sender, NodeAddress author, uint64_t lamport) {
  if (!IsMember(author)) {
    Refused(
        counters_.refused_stranger,
        fmt::format("a change by {}, which is not a member of the exercise", author.ToString()));
    return false;
  }
  if (RoleOf(author, NodeRole::kNode) == NodeRole::kObserver) {
    Refused(counters_.refused_role,
            fmt::format("a change by {}, an observer, which creates nothing", author.ToString()));
    return false;
  }
  return AdmitsClock(sender, lamport);
}

bool Replica::AdmitsClock(NodeAddress sender, uint64_t lamport) {
  if (lamport >= kMaxLamport || lamport > lamport_ + kMaxLamportLead) {
    Refused(counters_.refused_lamport,
            fmt::format("a PDU from {} with Lamport clock {}, more than {} ahead of {}",
                        sender.ToString(), lamport, kMaxLamportLead, lamport_));
    return false;
  }
  return true;
}

bool Replica::AdmitsRole(NodeAddress sender, NodeRole role, std::string_view what) {
  if (RoleOf(sender, role) == role) return true;
  Refused(counters_.refused_role,
          fmt::format("{} from {} claiming role {}; the exercise file says {}", what,
                      sender.ToString(), NodeRoleName(role), NodeRoleName(RoleOf(sender, role))));
  return false;
}

bool Replica::AdmitsSender(NodeAddress sender) {
  if (!IsMember(sender)) {
    Refused(counters_.refused_stranger,
            fmt::format("a PDU from {}, which is not a member of the exercise", sender.ToString()));
    return false;
  }
  if (exercise_ground_) {
    Refused(counters_.refused_ground,
            fmt::format("{}: a PDU from {}: this process is on ground {} ({}), not the "
                        "exercise's {}",
                        log::kGroundMismatchMarker, sender.ToString(), ground_digest_.ToHex(),
                        config_.ground_source, exercise_ground_->ToHex()));
    return false;
  }
  // A member whose ground is not known yet is believed: every member's first PDU is a MaxFeature
  // naming it, and one on another ground never signs on where there is a server, so it issues no
  // change (docs/pdu.md "Ground identity").
  auto known = peer_grounds_.find(sender);
  if (known == peer_grounds_.end() || known->second == ground_digest_) return true;
  Refused(counters_.refused_ground,
          fmt::format("{}: a PDU from {}, whose ground is {}; this process's is {} ({})",
                      log::kGroundMismatchMarker, sender.ToString(), known->second.ToHex(),
                      ground_digest_.ToHex(), config_.ground_source));
  return false;
}

bool Replica::AdmitsGround(NodeAddress sender, NodeRole role, const dtpdu::max_feature_t& pdu) {
  const TerrainDigest theirs{static_cast<uint64_t>(pdu.ground_digest[0]),
                             static_cast<uint64_t>(pdu.ground_digest[1])};
  peer_grounds_[sender] = theirs;
  if (theirs == ground_digest_) return true;
  // The exercise's ground is the server's; the standby's while no server has been heard on this
  // replica's ground. A server is its own authority (its database holds its ground's identity).
  bool authority = role == NodeRole::kServer;
  if (role == NodeRole::kStandby && config_.role != NodeRole::kStandby) {
    authority = true;
    for (const auto& [peer, digest] : peer_grounds_) {
      if (digest == ground_digest_ && RoleOf(peer, NodeRole::kNode) == NodeRole::kServer) {
        authority = false;
      }
    }
  }
  if (authority && config_.role != NodeRole::kServer && !exercise_ground_) {
    exercise_ground_ = theirs;
    exercise_ground_reporter_ = sender;
    // An observer and a standby are signed on from the start: no longer. A node never will be
    // (its sign-on needs the server's answer); it goes on asking, so the others keep naming it.
    signed_on_ = false;
    DT_LOG_ERROR(
        "{}: {} {} loaded ground {} from {}, but the exercise's ground ({} {}) is {}: this "
        "process takes no part (start it on the exercise's ground)",
        log::kGroundMismatchMarker, NodeRoleName(config_.role), config_.address.ToString(),
        ground_digest_.ToHex(), config_.ground_source, NodeRoleName(role), sender.ToString(),
        theirs.ToHex());
  }
  Refused(counters_.refused_ground,
          fmt::format("{}: {} {} is on ground {}; this process's is {} ({})",
                      log::kGroundMismatchMarker, NodeRoleName(role), sender.ToString(),
                      theirs.ToHex(), ground_digest_.ToHex(), config_.ground_source));
  return false;
}

}  // namespace dt

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
  if (IsMember(sender)) return true;
  Refused(counters_.refused_stranger,
          fmt::format("a PDU from {}, which is not a member of the exercise", sender.ToString()));
  return false;
}

}  // namespace dt

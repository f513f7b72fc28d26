// The rules that close a gap no live replica can fill with a void (docs/protocol.md, "Lost
// changes"): the author's own, for an earlier incarnation's changes, and the slot authority's,
// for an author gone for good.
#include <algorithm>

#include <fmt/format.h>

#include "engine/repair_rule.h"
#include "engine/replica.h"
#include "log/log.h"

namespace dt {

bool Replica::CanVoid(int64_t start, int64_t end) {
  if (own_feature_number_ + (end - start + 1) > kMaxSerial) {
    DT_LOG_WARN("replica {}: not voiding {}..{}: no feature numbers left",
                config_.address.ToString(), start, end);
    return false;
  }
  if (Status s = ReserveFeatureNumbers(own_feature_number_ + (end - start + 1)); !s) {
    DT_LOG_WARN("replica {}: not voiding {}..{} yet: {}", config_.address.ToString(), start, end,
                s.error().message);
    return false;
  }
  return true;
}

void Replica::IssueVoids(NodeAddress author, int64_t start, int64_t end) {
  for (int64_t seq = start; seq <= end; ++seq) {
    Change c;
    c.kind = ChangeKind::kDestruct;
    // A number of this replica's own that was never issued: the tombstone destroys nothing.
    c.id = {config_.address.site, config_.address.host,
            static_cast<uint32_t>(++own_feature_number_)};
    c.params.type = FeatureType::kCrater;
    c.stamp.changed_by = author;
    c.stamp.change_seq = static_cast<uint32_t>(seq);
    c.stamp.lamport = ++lamport_;
    ++counters_.voided;
    Issue(c);
  }
}

void Replica::VoidLostOwnChanges() {
  // Changes of this node's previous incarnation that every live replica was asked for and none
  // holds are lost; filling their sequences with void changes (a tombstone of a fresh, never
  // issued feature number) closes the gap for everyone (docs/protocol.md, "Lost changes").
  auto it = logs_.find(config_.address);
  if (!signed_on_ || it == logs_.end() || !it->second.has_gap()) return;
  const auto candidates = Candidates(config_.address);
  // Asked each candidate three times over without progress: a lost answer is not taken for a
  // lost change. A server's claim is its durable gap-free point, so a gap it claims is held.
  if (candidates.empty() || scheduler_.attempts(config_.address) <= 3 * candidates.size()) return;
  auto [start, end] = it->second.FirstGap();
  // A server acknowledged it: the change is durable there, however long that server stays
  // silent (a blocked transport, a restart), so it is never voided.
  if (start <= acknowledged_change_seq_) return;
  for (const auto& [reporter, seq] : it->second.reports()) {
    auto p = peers_.find(reporter);
    if (p != peers_.end() && IsServerRole(p->second.role) && seq >= start) return;
  }
  end = std::min(end, own_change_seq_);
  if (!CanVoid(start, end)) return;
  IssueVoids(config_.address, start, end);
  DT_LOG_INFO(
      "replica {}: changes {}..{} of an earlier incarnation are held by no live replica; "
      "voided",
      config_.address.ToString(), start, end);
}

bool Replica::HeldByLiveServer(const ChangeLog& log, int64_t seq) const {
  for (const auto& [reporter, claimed] : log.reports()) {
    auto p = peers_.find(reporter);
    if (p != peers_.end() && IsServerRole(p->second.role) && !IsSilent(reporter) &&
        claimed >= seq) {
      return true;
    }
  }
  return false;
}

void Replica::GiveUpOnGoneAuthors() {
  if (!signed_on_ || config_.gap_give_up_ms <= 0) return;
  for (const auto& [author, log] : logs_) {
    if (author == config_.address) continue;  // VoidLostOwnChanges
    if (!log.has_gap()) {
      gap_stuck_.erase(author);
      continue;
    }
    auto [start, end] = log.FirstGap();
    // The clock starts again whenever the first gap moves: progress, however slow, is no loss.
    auto [it, fresh] = gap_stuck_.try_emplace(author, GapStuck{start, now_ms_});
    if (fresh || it->second.start != start) {
      it->second = GapStuck{start, now_ms_};
      continue;
    }
    // The author itself voids what it lost when it comes back; this is for one that does not.
    if (now_ms_ - it->second.since_ms < config_.gap_give_up_ms || !IsSilent(author)) continue;
    // Every live candidate was asked three times over without progress, as for own voids.
    const auto candidates = Candidates(author);
    if (!candidates.empty() && scheduler_.attempts(author) <= 3 * candidates.size()) continue;
    if (HeldByLiveServer(log, start)) continue;
    if (start > log.max_held()) {
      // Only claims say these exist, and no claimant sent them when asked: drop the claims
      // rather than fill slots no one is known to have used. Any replica may: it decides
      // nothing for the others (a claim can outlive what backed it, e.g. a peer restarted
      // without state within silence_ms).
      DT_LOG_WARN(
          "replica {}: changes {}..{} of {} were claimed but never sent by any live replica, and "
          "{} has been silent for {} ms; the claims are dropped",
          config_.address.ToString(), start, end, author.ToString(), author.ToString(),
          now_ms_ - it->second.since_ms);
      logs_.at(author).ForgetClaimsBeyondHeld();
      gap_stuck_.erase(it);
      continue;
    }
    // One replica gives up, so the slot gets one void: the slot's authority among the live
    // replicas (a server, else a standby, else the lowest address). Two that see liveness
    // differently may both void it; anti-entropy then keeps the authority's copy.
    if (observer()) continue;  // never the authority: it issues nothing, voids included
    std::vector<SlotHolder> live{{config_.address, config_.role}};
    for (const auto& [addr, p] : peers_) {
      if (addr != config_.address && !IsSilent(addr)) live.push_back({addr, p.role});
    }
    if (SlotAuthority(author, live) != config_.address) continue;
    end = std::min(end, start + int64_t{config_.playback_window} - 1);
    if (!CanVoid(start, end)) continue;
    DT_LOG_WARN(
        "replica {}: changes {}..{} of {} are held by no live replica and {} has been silent "
        "for {} ms; given up on (voided)",
        config_.address.ToString(), start, end, author.ToString(), author.ToString(),
        now_ms_ - it->second.since_ms);
    counters_.gave_up += static_cast<uint64_t>(end - start + 1);
    IssueVoids(author, start, end);
    it->second = GapStuck{end + 1, now_ms_};
  }
}

}  // namespace dt

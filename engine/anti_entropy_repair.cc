// Repairing a slot whose copies differ: which copy wins, putting it in the log and the records,
// and storing it (docs/protocol.md, "Anti-entropy").
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "base/demand.h"
#include "engine/anti_entropy.h"
#include "engine/change_hash.h"
#include "engine/repair_rule.h"
#include "log/log.h"

namespace dt {

std::optional<NodeAddress> AntiEntropy::Authority(NodeAddress author, int64_t seq) const {
  std::vector<SlotHolder> holders{{config_.self, config_.role}};
  for (const auto& [addr, view] : peers_) {
    auto held = view.gap_free.find(author);
    if (held != view.gap_free.end() && held->second.seq >= seq) {
      holders.push_back({addr, view.role});
    }
  }
  return SlotAuthority(author, holders);
}

void AntiEntropy::Decide(NodeAddress peer, const Change& theirs) {
  const NodeAddress author = theirs.author();
  const int64_t seq = theirs.stamp.change_seq;
  const ChangeLog* log = FindLog(author);
  const Change* mine = log == nullptr ? nullptr : log->Find(seq);
  if (mine == nullptr || *mine == theirs) return;  // a gap the copy filled, or nothing differs
  const std::optional<NodeAddress> authority = Authority(author, seq);
  const bool take = authority ? *authority == peer : LowerCopy(theirs, *mine);
  const std::string why =
      authority ? fmt::format("the slot's authority is {}", authority->ToString())
                : std::string("no server, standby or author holds the slot: the lower copy wins");
  if (!take) {
    DT_LOG_INFO("replica {}: keeps its copy of {}:{} over {}'s ({})", config_.self.ToString(),
                author.ToString(), seq, peer.ToString(), why);
    return;
  }
  const Change old_copy = *mine;
  if (config_.role == NodeRole::kServer) {
    // Only a server with a lower address outranks a server: two servers in one exercise.
    DT_LOG_WARN("replica {}: replaces its stored (acknowledged) copy of {}:{} by server {}'s",
                config_.self.ToString(), author.ToString(), seq, peer.ToString());
  }
  Put(old_copy, theirs);
  if (config_.store != nullptr) {
    pending_store_.push_back(theirs);
    FlushStore();
  }
  ++stats_.slots_repaired;
  DT_LOG_INFO("replica {}: repaired {}:{}: took {}'s copy ({})", config_.self.ToString(),
              author.ToString(), seq, peer.ToString(), why);
  replaced_(old_copy, theirs);
}

void AntiEntropy::Put(const Change& old_copy, const Change& change) {
  auto lit = logs_.find(change.author());
  DT_DEMAND(lit != logs_.end() && lit->second.Replace(change));  // callers checked
  prefixes_[change.author()].Replace(change.stamp.change_seq, ChangeHash(old_copy),
                                     ChangeHash(change));
  // Last writer wins cannot be undone by one change: the records of both features are applied
  // again from every change of them held.
  std::vector<FeatureId> ids{old_copy.id};
  if (change.id != old_copy.id) ids.push_back(change.id);
  RebuildRecords(ids);
}

void AntiEntropy::RebuildRecords(const std::vector<FeatureId>& ids) {
  std::vector<std::vector<const Change*>> of(ids.size());
  for (const auto& [author, log] : logs_) {
    for (const Change* c : log.Range(1, log.max_held())) {
      for (size_t i = 0; i < ids.size(); ++i) {
        if (c->id == ids[i]) of[i].push_back(c);
      }
    }
  }
  for (size_t i = 0; i < ids.size(); ++i) records_.Rebuild(ids[i], of[i]);
}

void AntiEntropy::FlushStore() {
  const Status s = config_.store->Replace(pending_store_);
  if (!s) {
    if (!store_failing_) {
      DT_LOG_ERROR("replica {}: storing {} repaired changes failed; retried every tick: {}",
                   config_.self.ToString(), pending_store_.size(), s.error().message);
    }
    store_failing_ = true;
    return;
  }
  store_failing_ = false;
  pending_store_.clear();
}

Status AntiEntropy::Overwrite(const Change& change) {
  const ChangeLog* log = FindLog(change.author());
  const Change* held = log == nullptr ? nullptr : log->Find(change.stamp.change_seq);
  if (held == nullptr) {
    return Error{fmt::format("replica {} holds no change {}:{} to overwrite",
                             config_.self.ToString(), change.author().ToString(),
                             change.stamp.change_seq)};
  }
  const Change old_copy = *held;
  Put(old_copy, change);
  replaced_(old_copy, change);
  return Status::Ok();
}

}  // namespace dt

// An observer drops the changes only it holds: their author crashed before anyone else got them,
// so they are in no one else's log and never will be (docs/protocol.md, "Observers").
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "base/demand.h"
#include "engine/anti_entropy.h"
#include "engine/prefix_hashes.h"
#include "log/log.h"

namespace dt {

int64_t AntiEntropy::HeldElsewhere(NodeAddress author, const ChangeLog& log) const {
  int64_t held = 0;
  // Peers heard within ForgetMs, by their last summary (an author it no longer names is gone
  // from it after ForgetMs too).
  for (const auto& [addr, view] : peers_) {
    auto h = view.gap_free.find(author);
    if (h != view.gap_free.end()) held = std::max({held, h->second.seq, h->second.max_held});
  }
  // A live claim says the change exists somewhere: the author's own counter, a server's durable
  // point. Its holder will fill the slot (or the author void it), and anti-entropy then repairs
  // this copy: nothing to drop. Claims of reporters gone silent are forgotten by the replica.
  for (const auto* claims : {&log.reports(), &log.held_by()}) {
    for (const auto& [by, seq] : *claims) held = std::max(held, seq);
  }
  return held;
}

void AntiEntropy::DropWhatOnlyThisHolds() {
  for (auto& [author, log] : logs_) {
    const int64_t mine = log.max_held();
    const int64_t elsewhere = HeldElsewhere(author, log);
    if (mine <= elsewhere) {
      beyond_.erase(author);
      continue;
    }
    auto it = beyond_.try_emplace(author, Beyond{mine, now_ms_}).first;
    if (it->second.held != mine) it->second = Beyond{mine, now_ms_};  // a new change
    const int64_t since = it->second.since_ms;
    // The author's word: its own summary of its log, received a period after this replica first
    // held more than anyone. A summary sent before the change left the author arrives almost
    // always within a period of it; one reordered further only makes the drop early, and a drop
    // heals itself (the holders' next summaries report the slot, so it is fetched again).
    bool authors_word = false;
    if (auto p = peers_.find(author); p != peers_.end()) {
      auto h = p->second.gap_free.find(author);
      authors_word =
          h != p->second.gap_free.end() && h->second.seen_ms >= since + config_.period_ms;
    }
    // An author that is gone, or names none of its own changes: nobody has reported the slot
    // for as long as a gap is waited for before it is given up on.
    const bool unreported =
        config_.drop_unreported_ms > 0 && now_ms_ - since >= config_.drop_unreported_ms;
    if (!authors_word && !unreported) continue;
    const std::string why =
        authors_word ? fmt::format("{}'s own summary holds less", author.ToString())
                     : fmt::format("nobody has reported them for {} ms", now_ms_ - since);
    beyond_.erase(it);
    Drop(author, elsewhere, why);
  }
}

void AntiEntropy::Drop(NodeAddress author, int64_t keep_upto, const std::string& why) {
  ChangeLog& log = logs_.at(author);
  std::vector<int64_t> seqs;
  for (const Change* c : log.Range(keep_upto + 1, log.max_held())) {
    seqs.push_back(c->stamp.change_seq);
  }
  std::set<FeatureId> ids;
  for (int64_t seq : seqs) {
    auto gone = log.Remove(seq);
    DT_DEMAND(gone);  // just listed as held
    ids.insert(gone->id);
  }
  // Sums past the gap-free point are of changes no longer held: Extend hashes whatever fills
  // those slots later.
  prefixes_[author].Truncate(log.contiguous());
  RebuildRecords(std::vector<FeatureId>(ids.begin(), ids.end()));
  stats_.slots_dropped += seqs.size();
  DT_LOG_WARN(
      "replica {}: dropped {}'s changes {}..{} ({} held), which only it holds: no live replica "
      "holds or claims more than {}, and {}",
      config_.self.ToString(), author.ToString(), keep_upto + 1, seqs.empty() ? 0 : seqs.back(),
      seqs.size(), keep_upto, why);
}

}  // namespace dt

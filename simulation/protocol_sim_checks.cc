// The protocol simulation's checks after the heal: every replica caught up with the server's
// digest, the oracle of issued changes, the repaired corruption and the observer.
#include <cstdio>

#include <fmt/format.h>

#include "simulation/protocol_sim.h"

#include "engine/record_store.h"
#include "terrain/terrain_digest.h"

namespace dt::sim {

std::string SimRun::CheckCorruptionRepaired() {
  if (!corruption_ || !cluster_->alive(corruption_->replica) ||
      crashes_[corruption_->replica] != corruption_->crashes) {
    return "";  // nothing corrupted, or the replica restarted since and holds no corruption
  }
  const Corruption& c = *corruption_;
  Replica& r = cluster_->at(c.replica);
  const Change* mine = r.log(c.author)->Find(c.seq);
  const ChangeLog* server_log = cluster_->at(kServer).log(c.author);
  const Change* theirs = server_log == nullptr ? nullptr : server_log->Find(c.seq);
  if (mine == nullptr || theirs == nullptr || !(*mine == *theirs)) {
    return fmt::format("{}'s corrupted copy of {}:{} was not repaired", c.replica.ToString(),
                       c.author.ToString(), c.seq);
  }
  if (r.anti_entropy().stats().slots_repaired == 0) {
    return fmt::format("{}'s corrupted copy of {}:{} is not counted as repaired",
                       c.replica.ToString(), c.author.ToString(), c.seq);
  }
  return "";
}

std::string SimRun::CheckObserver() {
  Replica& server = cluster_->at(kServer);
  Replica& view = cluster_->at(kView);
  observer_dropped_ = view.anti_entropy().stats().slots_dropped;
  if (view.diverged()) return "the observer is still diverged after healing";
  if (!view.caught_up()) return "the observer is not caught up after healing";
  std::vector<NodeAddress> authors = cluster_->live();
  authors.push_back(kGhost);
  for (NodeAddress author : authors) {
    const ChangeLog* theirs = server.log(author);
    const ChangeLog* mine = view.log(author);
    if (theirs != nullptr) {
      for (const Change* c : theirs->Range(1, theirs->max_held())) {
        const Change* o = mine == nullptr ? nullptr : mine->Find(c->stamp.change_seq);
        if (o == nullptr || !(*o == *c)) {
          return fmt::format("the observer does not hold the server's change {}:{}",
                             author.ToString(), c->stamp.change_seq);
        }
      }
    }
    // A change only the observer holds (its author crashed before anyone else got it) is
    // dropped by now (docs/protocol.md, "Observers").
    if (mine == nullptr) continue;
    for (const Change* c : mine->Range(1, mine->max_held())) {
      if (theirs == nullptr || theirs->Find(c->stamp.change_seq) == nullptr) {
        return fmt::format(
            "the observer still holds {}:{}, which the server does not ({} changes dropped)",
            author.ToString(), c->stamp.change_seq, observer_dropped_);
      }
    }
  }
  if (view.Digest() != server.Digest()) {
    return fmt::format("the observer holds the server's changes but its digest {} is not {}",
                       view.Digest(), server.Digest());
  }
  return "";
}

std::string SimRun::Check() {
  Replica& server = cluster_->at(kServer);
  const std::string digest = server.Digest();
  for (NodeAddress a : cluster_->live()) {
    if (a == kView) {
      if (std::string f = CheckObserver(); !f.empty()) return f;
      continue;
    }
    Replica& r = cluster_->at(a);
    if (r.diverged()) {
      const auto d = r.divergences().front();
      return fmt::format("{} is still diverged after healing: {}'s log with {}, changes {}..{}",
                         a.ToString(), d.author.ToString(), d.peer.ToString(), d.first_seq,
                         d.last_seq);
    }
    if (!r.caught_up()) {
      std::string logs;
      std::vector<NodeAddress> authors = cluster_->live();
      authors.push_back(kGhost);
      for (NodeAddress author : authors) {
        if (const ChangeLog* l = r.log(author)) {
          logs += fmt::format(" {}:[{} of {}", author.ToString(), l->contiguous(), l->max_known());
          for (const auto& [by, seq] : l->reports())
            logs += fmt::format(" {}says{}", by.ToString(), seq);
          for (const auto& [by, seq] : l->held_by())
            logs += fmt::format(" {}holds{}", by.ToString(), seq);
          if (l->max_held() > 0) logs += fmt::format(" held{}", l->max_held());
          logs += "]";
        }
      }
      if (trace_) {
        for (NodeAddress x : cluster_->live()) {
          if (const ChangeLog* g = cluster_->at(x).log(kGhost)) {
            std::printf("%s's log of the gone author: %lld of %lld, held %lld, gave_up %llu\n",
                        x.ToString().c_str(), static_cast<long long>(g->contiguous()),
                        static_cast<long long>(g->max_known()),
                        static_cast<long long>(g->max_held()),
                        static_cast<unsigned long long>(cluster_->at(x).counters().gave_up));
          }
        }
      }
      return fmt::format("{} is not caught up after healing:{}", a.ToString(), logs);
    }
    for (const auto& [author, n] : incarnation_) {
      const ChangeLog* mine = r.log(author);
      const ChangeLog* theirs = server.log(author);
      if (mine == nullptr || theirs == nullptr) continue;
      for (const Change* c : mine->Range(1, mine->max_held())) {
        const Change* o = theirs->Find(c->stamp.change_seq);
        if (o != nullptr && !(*o == *c)) {
          return fmt::format("{} and the server hold different changes {}:{} (a reused sequence)",
                             a.ToString(), author.ToString(), c->stamp.change_seq);
        }
      }
    }
    if (r.Digest() != digest && trace_) {
      for (const auto& [author, n] : incarnation_) {
        for (Replica* x : {&r, &server}) {
          std::string held;
          if (const ChangeLog* l = x->log(author)) {
            for (const Change* c : l->Range(1, l->max_held())) {
              held += fmt::format(" {}@{}:{}:{}", c->stamp.change_seq, c->stamp.lamport,
                                  static_cast<int>(c->kind), c->id.ToString());
            }
          }
          std::printf("  %s's log of %s:%s\n", x->config().address.ToString().c_str(),
                      author.ToString().c_str(), held.c_str());
        }
      }
    }
    if (r.Digest() != digest) {
      return fmt::format("{} digest {} != server digest {} ({} vs {} live features)", a.ToString(),
                         r.Digest(), digest, r.live_feature_count(), server.live_feature_count());
    }
  }
  // The oracle: what the server holds must be exactly the issued changes that survived, with
  // identical content, and materialise to the same terrain.
  RecordStore reference(SimGround());
  size_t present = 0;
  for (const Issued& i : issued_) {
    if (i.replaced) continue;
    const NodeAddress author = i.change.author();
    const ChangeLog* log = server.log(author);
    const Change* held = log != nullptr ? log->Find(i.change.stamp.change_seq) : nullptr;
    const bool acked = i.change.stamp.change_seq <= max_ack_[{author, i.incarnation}];
    const bool author_survived = incarnation_[author] == i.incarnation;
    if (held == nullptr) {
      if (acked) {
        return fmt::format("acknowledged change {}:{} was lost", author.ToString(),
                           i.change.stamp.change_seq);
      }
      if (author_survived) {
        return fmt::format("change {}:{} of a node that never crashed was lost", author.ToString(),
                           i.change.stamp.change_seq);
      }
      continue;
    }
    const bool held_void = held->kind == ChangeKind::kDestruct && issued_ids_.count(held->id) == 0;
    if (!(*held == i.change) && held_void && !acked && !author_survived) {
      continue;  // lost with its incarnation, and its sequence voided by the next one
    }
    if (!(*held == i.change)) {
      return fmt::format("change {}:{} is held with other content than issued", author.ToString(),
                         i.change.stamp.change_seq);
    }
    (void)reference.Apply(i.change);
    ++present;
  }
  // The gone author's log: its one change (unless every copy was dropped on the way) and the
  // voids that closed the gap before it, tombstones of numbers no one issued.
  const ChangeLog* ghost_log = ghost_change_ ? server.log(kGhost) : nullptr;
  if (const ChangeLog* log =
          ghost_log != nullptr && ghost_log->max_held() > 0 ? ghost_log : nullptr) {
    const int64_t seq = ghost_change_->stamp.change_seq;
    if (log->contiguous() != seq || log->max_held() != seq) {
      return fmt::format("the server holds the gone author's log up to {} of {}, not 1..{}",
                         log->contiguous(), log->max_held(), seq);
    }
    for (const Change* c : log->Range(1, seq - 1)) {
      if (c->kind != ChangeKind::kDestruct || issued_ids_.count(c->id) != 0 ||
          OriginOf(c->id) == kGhost) {
        return fmt::format("the gone author's change {} is not a void", c->stamp.change_seq);
      }
    }
    if (!(*log->Find(seq) == *ghost_change_)) return "the gone author's change is changed";
    if (trace_) {
      for (NodeAddress a : cluster_->live()) {
        std::printf("%s gave up on %llu changes\n", a.ToString().c_str(),
                    static_cast<unsigned long long>(cluster_->at(a).counters().gave_up));
      }
    }
    (void)reference.Apply(*ghost_change_);
  }
  // Everything else the server holds must be a void: a tombstone of a never-issued number.
  size_t held_total = 0, voids = 0;
  for (const auto& [a, n] : incarnation_) {
    const ChangeLog* log = server.log(a);
    if (log == nullptr) continue;
    held_total += log->size();
    for (const Change* c : log->Range(1, log->max_held())) {
      if (c->kind == ChangeKind::kDestruct && issued_ids_.count(c->id) == 0 &&
          OriginOf(c->id) == a) {
        ++voids;
      }
    }
  }
  if (held_total != present + voids) {
    return fmt::format("the server holds {} changes, {} of them issued and {} voids", held_total,
                       present, voids);
  }
  if (reference.live_count() != server.live_feature_count()) {
    return fmt::format("expected {} live features, the server has {}", reference.live_count(),
                       server.live_feature_count());
  }
  if (ComputeDigest(reference.terrain()).ToHex() != digest) {
    return "the server's terrain differs from the oracle's";
  }
  return "";
}

}  // namespace dt::sim

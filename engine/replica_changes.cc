// Accepting and publishing changes: what a replica does with a Construct, EarthMove, Update or
// Destruct it receives or sends (docs/protocol.md, "Changes and their order").
#include <algorithm>

#include <fmt/format.h>

#include "engine/replica.h"
#include "log/log.h"

namespace dt {

void Replica::ObserveLamport(uint64_t lamport) { lamport_ = std::max(lamport_, lamport); }

void Replica::NoteOwn(const Change& change) {
  if (change.author() == config_.address) {
    own_change_seq_ = std::max<int64_t>(own_change_seq_, change.stamp.change_seq);
    LogOf(config_.address).RaiseFloor(own_change_seq_);
  }
  if (OriginOf(change.id) == config_.address) {
    own_feature_number_ = std::max<int64_t>(own_feature_number_, change.id.number);
  }
}

bool Replica::Accept(const Change& change, bool from_store) {
  ObserveLamport(change.stamp.lamport);
  if (!LogOf(change.author()).Insert(change)) return false;
  // Dates the first change of an answer, so the playback window can follow the round trip.
  if (!from_store) scheduler_.OnArrival(change.author(), change.stamp.change_seq, now_ms_);
  NoteOwn(change);
  auto& max = max_feature_[OriginOf(change.id)];
  max = std::max<int64_t>(max, change.id.number);
  if (records_.Apply(change) == RecordStore::Outcome::kApplied) {
    ++counters_.applied;
  } else {
    ++counters_.ignored_stale;
  }
  if (config_.store != nullptr && !from_store) pending_store_.push_back(change);
  return true;
}

void Replica::Publish(const Change& change, std::optional<NodeAddress> playback_for) {
  Result<int64_t> sent = Error{""};
  switch (change.kind) {
    case ChangeKind::kConstruct: {
      if (change.params.type == FeatureType::kEarthMove) {
        auto pdu = ToEarthMove(ToFeaturePdu(change));
        if (playback_for) {
          pdu.is_playback = true;
          pdu.playback_for = ToPdu(*playback_for);
        }
        sent = bus_.Publish(pdu);
        break;
      }
      auto pdu = ToConstruct(ToFeaturePdu(change));
      if (playback_for) {
        pdu.is_playback = true;
        pdu.playback_for = ToPdu(*playback_for);
      }
      sent = bus_.Publish(pdu);
      break;
    }
    case ChangeKind::kUpdate: {
      auto pdu = ToUpdate(ToFeaturePdu(change));
      if (playback_for) {
        pdu.is_playback = true;
        pdu.playback_for = ToPdu(*playback_for);
      }
      sent = bus_.Publish(pdu);
      break;
    }
    case ChangeKind::kDestruct: {
      auto pdu = ToDestruct(ToDestructPdu(change));
      if (playback_for) {
        pdu.is_playback = true;
        pdu.playback_for = ToPdu(*playback_for);
      }
      sent = bus_.Publish(pdu);
      break;
    }
  }
  if (sent) {
    ++counters_.sent;
  } else {
    DT_LOG_WARN("replica {}: sending change {}:{} failed: {}", config_.address.ToString(),
                change.author().ToString(), change.stamp.change_seq, sent.error().message);
  }
}

void Replica::HeardFrom(NodeAddress sender, std::optional<NodeRole> role) {
  if (sender == config_.address) return;
  // An observer's playback requests are answered, but it is no peer: never a candidate, never
  // waited for in a sign-on, never a live holder when giving up (docs/protocol.md, "Observers").
  if (RoleOf(sender, NodeRole::kNode) == NodeRole::kObserver) return;
  Peer& p = peers_[sender];
  p.last_heard_ms = now_ms_;
  if (role) p.role = *role;
}

void Replica::OnConstruct(const dtpdu::construct_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  HeardFrom(sender, std::nullopt);
  auto f = FromConstruct(pdu);
  if (!f) {
    ++counters_.rejected;
    return;
  }
  const Change c = ChangeFrom(f.value(), ChangeKind::kConstruct);
  if (Admits(sender, c.author(), c.stamp.lamport)) Accept(c, false);
}

void Replica::OnEarthMove(const dtpdu::earth_move_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  HeardFrom(sender, std::nullopt);
  auto f = FromEarthMove(pdu);
  if (!f) {
    ++counters_.rejected;
    return;
  }
  // An earth move is a Construct of its own feature: logged, played back and stored as one.
  const Change c = ChangeFrom(f.value(), ChangeKind::kConstruct);
  if (Admits(sender, c.author(), c.stamp.lamport)) Accept(c, false);
}

void Replica::OnUpdate(const dtpdu::update_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  HeardFrom(sender, std::nullopt);
  auto f = FromUpdate(pdu);
  if (!f) {
    ++counters_.rejected;
    return;
  }
  const Change c = ChangeFrom(f.value(), ChangeKind::kUpdate);
  if (Admits(sender, c.author(), c.stamp.lamport)) Accept(c, false);
}

void Replica::OnDestruct(const dtpdu::destruct_t& pdu) {
  ++counters_.received;
  const NodeAddress sender = FromPdu(pdu.sender);
  if (!AdmitsSender(sender)) return;
  HeardFrom(sender, std::nullopt);
  auto d = FromDestruct(pdu);
  if (!d) {
    ++counters_.rejected;
    return;
  }
  const Change c = ChangeFrom(d.value());
  if (Admits(sender, c.author(), c.stamp.lamport)) Accept(c, false);
}

}  // namespace dt

#include "pdu/conversion.h"

#include <algorithm>
#include <cstdint>
#include <type_traits>

#include <fmt/format.h>

#include "base/demand.h"
#include "pdu/pdu_type.h"
#include "terrain/height_grid.h"

namespace dt {
namespace {

// The author of a change: a Construct calls it created_by (it is always the feature's origin),
// Update and Destruct changed_by. The different name gives Construct and Update different LCM
// fingerprints (docs/pdu.md "Encoding").
template <typename Pdu>
auto& AuthorOf(Pdu& pdu) {
  if constexpr (std::is_same_v<std::remove_const_t<Pdu>, dtpdu::construct_t>) {
    return pdu.created_by;
  } else if constexpr (std::is_same_v<std::remove_const_t<Pdu>, dtpdu::earth_move_t>) {
    return pdu.moved_by;
  } else {
    return pdu.changed_by;
  }
}

// Construct and Update have the same fields; one template serves both so they cannot drift.
template <typename Pdu>
Pdu FeatureToPdu(const FeaturePdu& f) {
  Pdu pdu{};
  pdu.origin = ToPdu(OriginOf(f.id));
  pdu.feature_number = f.id.number;
  pdu.feature_type = static_cast<int16_t>(f.params.type);
  AuthorOf(pdu) = ToPdu(f.change.changed_by);
  pdu.change_seq = f.change.change_seq;
  pdu.lamport = static_cast<int64_t>(f.change.lamport);
  pdu.position_m[0] = f.params.x_m;
  pdu.position_m[1] = 0.0;  // every node places the feature on its own ground
  pdu.position_m[2] = f.params.z_m;
  pdu.direction_rad = f.params.direction_rad;
  pdu.height_m[0] = f.params.height_m[0];
  pdu.height_m[1] = f.params.height_m[1];
  for (int i = 0; i < 3; ++i) pdu.length_m[i] = f.params.length_m[i];
  pdu.width_m = f.params.width_m;
  pdu.material = static_cast<int16_t>(f.params.material);
  pdu.status = static_cast<int32_t>(f.params.status);
  pdu.num_vertex_edits = static_cast<int16_t>(f.params.vertex_edits.size());
  pdu.vertex_edits.reserve(f.params.vertex_edits.size());
  for (const auto& e : f.params.vertex_edits) {
    dtpdu::crater_vertex_edit_t out{};
    out.spoke = e.spoke;
    out.ring = e.ring;
    out.offset_m = e.offset_m;
    pdu.vertex_edits.push_back(out);
  }
  pdu.num_points = static_cast<int16_t>(f.params.points.size());
  pdu.points.reserve(f.params.points.size());
  for (const auto& q : f.params.points) {
    dtpdu::feature_point_t out{};
    out.x_m = q.x_m;
    out.z_m = q.z_m;
    out.height_m = q.height_m;
    out.width_m = q.width_m;
    pdu.points.push_back(out);
  }
  return pdu;
}

Status CheckSerial(const char* field, int64_t value, int64_t min) {
  if (value < min || value > kMaxSerial) {
    return Error{fmt::format("{} = {} is outside [{}, {}]", field, value, min, kMaxSerial)};
  }
  return Status::Ok();
}

template <typename Pdu>
Result<ChangeStamp> StampFromPdu(const Pdu& pdu) {
  if (auto s = CheckSerial("change_seq", pdu.change_seq, 1); !s) return s.error();
  if (pdu.lamport < 1) return Error{fmt::format("lamport = {} is below 1", pdu.lamport)};
  ChangeStamp c;
  c.changed_by = FromPdu(AuthorOf(pdu));
  c.change_seq = static_cast<uint32_t>(pdu.change_seq);
  c.lamport = static_cast<uint64_t>(pdu.lamport);
  return c;
}

template <typename Pdu>
Result<FeatureId> IdFromPdu(const Pdu& pdu) {
  if (auto s = CheckSerial("feature_number", pdu.feature_number, 1); !s) return s.error();
  const NodeAddress origin = FromPdu(pdu.origin);
  return FeatureId{origin.site, origin.host, static_cast<uint32_t>(pdu.feature_number)};
}

Result<FeatureType> TypeFromPdu(int16_t raw) {
  if (raw < 0 || !IsValidFeatureType(static_cast<uint16_t>(raw))) {
    return Error{fmt::format("unknown feature type {}", raw)};
  }
  return static_cast<FeatureType>(raw);
}

template <typename Pdu>
Result<FeaturePdu> FeatureFromPdu(const Pdu& pdu) {
  FeaturePdu f;
  auto id = IdFromPdu(pdu);
  if (!id) return id.error();
  f.id = id.value();
  auto stamp = StampFromPdu(pdu);
  if (!stamp) return stamp.error();
  f.change = stamp.value();
  auto type = TypeFromPdu(pdu.feature_type);
  if (!type) return type.error();
  if (type.value() == FeatureType::kEarthMove) {
    return Error{fmt::format("feature type {} (earth_move) travels only in EarthMove PDUs",
                             pdu.feature_type)};
  }
  f.params.type = type.value();
  if (pdu.material < 0 || !IsValidMaterial(static_cast<uint16_t>(pdu.material))) {
    return Error{fmt::format("unknown material {}", pdu.material)};
  }
  f.params.material = static_cast<Material>(pdu.material);
  if (pdu.status != 0 && pdu.status != 1) {
    return Error{fmt::format("unknown bridge status {}", pdu.status)};
  }
  f.params.status = static_cast<BridgeStatus>(pdu.status);
  f.params.x_m = pdu.position_m[0];
  f.params.z_m = pdu.position_m[2];
  f.params.direction_rad = pdu.direction_rad;
  f.params.height_m = {pdu.height_m[0], pdu.height_m[1]};
  f.params.length_m = {pdu.length_m[0], pdu.length_m[1], pdu.length_m[2]};
  f.params.width_m = pdu.width_m;
  if (pdu.num_vertex_edits < 0 || pdu.num_vertex_edits > kMaxVertexEdits ||
      static_cast<size_t>(pdu.num_vertex_edits) != pdu.vertex_edits.size()) {
    return Error{fmt::format("num_vertex_edits = {} is outside [0, {}] or disagrees with {} edits",
                             pdu.num_vertex_edits, kMaxVertexEdits, pdu.vertex_edits.size())};
  }
  f.params.vertex_edits.reserve(pdu.vertex_edits.size());
  for (const auto& e : pdu.vertex_edits) {
    f.params.vertex_edits.push_back(CraterVertexEdit{e.spoke, e.ring, e.offset_m});
  }
  if (pdu.num_points < 0 || pdu.num_points > kMaxFeaturePoints ||
      static_cast<size_t>(pdu.num_points) != pdu.points.size()) {
    return Error{fmt::format("num_points = {} is outside [0, {}] or disagrees with {} points",
                             pdu.num_points, kMaxFeaturePoints, pdu.points.size())};
  }
  f.params.points.reserve(pdu.points.size());
  for (const auto& q : pdu.points) {
    f.params.points.push_back(FeaturePoint{q.x_m, q.z_m, q.height_m, q.width_m});
  }
  return f;
}

}  // namespace

dtpdu::node_address_t ToPdu(const NodeAddress& address) {
  dtpdu::node_address_t out{};
  out.site = static_cast<int16_t>(address.site);
  out.host = static_cast<int16_t>(address.host);
  return out;
}

NodeAddress FromPdu(const dtpdu::node_address_t& address) {
  return NodeAddress{static_cast<uint16_t>(address.site), static_cast<uint16_t>(address.host)};
}

dtpdu::construct_t ToConstruct(const FeaturePdu& feature) {
  return FeatureToPdu<dtpdu::construct_t>(feature);
}
dtpdu::update_t ToUpdate(const FeaturePdu& feature) {
  return FeatureToPdu<dtpdu::update_t>(feature);
}

dtpdu::destruct_t ToDestruct(const DestructPdu& d) {
  dtpdu::destruct_t pdu{};
  pdu.origin = ToPdu(OriginOf(d.id));
  pdu.feature_number = d.id.number;
  pdu.feature_type = static_cast<int16_t>(d.type);
  pdu.changed_by = ToPdu(d.change.changed_by);
  pdu.change_seq = d.change.change_seq;
  pdu.lamport = static_cast<int64_t>(d.change.lamport);
  return pdu;
}

Result<FeaturePdu> FromConstruct(const dtpdu::construct_t& pdu) { return FeatureFromPdu(pdu); }
Result<FeaturePdu> FromUpdate(const dtpdu::update_t& pdu) { return FeatureFromPdu(pdu); }

dtpdu::earth_move_t ToEarthMove(const FeaturePdu& f) {
  dtpdu::earth_move_t pdu{};
  pdu.origin = ToPdu(OriginOf(f.id));
  pdu.feature_number = f.id.number;
  pdu.moved_by = ToPdu(f.change.changed_by);
  pdu.change_seq = f.change.change_seq;
  pdu.lamport = static_cast<int64_t>(f.change.lamport);
  const auto& deltas = f.params.post_deltas;
  if (deltas.empty()) return pdu;  // no rectangle; FromEarthMove refuses it
  int min_i = deltas.front().i, max_i = min_i;
  const int min_j = deltas.front().j, max_j = deltas.back().j;  // sorted by (j, i)
  for (const PostDelta& d : deltas) {
    min_i = std::min<int>(min_i, d.i);
    max_i = std::max<int>(max_i, d.i);
  }
  pdu.first_post_i = min_i;
  pdu.first_post_j = min_j;
  pdu.columns = static_cast<int16_t>(max_i - min_i + 1);
  pdu.rows = static_cast<int16_t>(max_j - min_j + 1);
  const int cells = pdu.columns * pdu.rows;
  pdu.num_mask_bytes = static_cast<int16_t>((cells + 7) / 8);
  pdu.changed_mask.assign(static_cast<size_t>(pdu.num_mask_bytes), 0);
  pdu.num_posts = static_cast<int16_t>(deltas.size());
  pdu.delta_mm.reserve(deltas.size());
  for (const PostDelta& d : deltas) {
    const int k = (d.j - min_j) * pdu.columns + (d.i - min_i);
    pdu.changed_mask[static_cast<size_t>(k / 8)] |= static_cast<uint8_t>(1u << (k % 8));
    DT_DEMAND(d.delta_mm <= INT16_MAX && d.delta_mm >= INT16_MIN);  // validated: +-10 000
    pdu.delta_mm.push_back(static_cast<int16_t>(d.delta_mm));
  }
  return pdu;
}

Result<FeaturePdu> FromEarthMove(const dtpdu::earth_move_t& pdu) {
  FeaturePdu f;
  auto id = IdFromPdu(pdu);
  if (!id) return id.error();
  f.id = id.value();
  auto stamp = StampFromPdu(pdu);
  if (!stamp) return stamp.error();
  f.change = stamp.value();
  f.params.type = FeatureType::kEarthMove;
  // Any grid's posts, elevation grounds beyond kMaxPostsPerSide included; whether the posts lie on
  // this exercise's grid is the bus's check (terrain_posts_x/z).
  if (pdu.first_post_i < 0 || pdu.first_post_i >= kMaxGridPostsPerSide || pdu.first_post_j < 0 ||
      pdu.first_post_j >= kMaxGridPostsPerSide) {
    return Error{fmt::format("first post ({}, {}) is outside [0, {})", pdu.first_post_i,
                             pdu.first_post_j, kMaxGridPostsPerSide)};
  }
  if (pdu.columns < 1 || pdu.columns > kMaxEarthMoveSpanPosts || pdu.rows < 1 ||
      pdu.rows > kMaxEarthMoveSpanPosts) {
    return Error{fmt::format("rectangle {} x {} posts is outside 1 .. {} each way", pdu.columns,
                             pdu.rows, kMaxEarthMoveSpanPosts)};
  }
  const int cells = pdu.columns * pdu.rows;
  if (pdu.num_mask_bytes != (cells + 7) / 8 ||
      static_cast<size_t>(pdu.num_mask_bytes) != pdu.changed_mask.size()) {
    return Error{fmt::format("num_mask_bytes = {} with {} bytes: a {} x {} rectangle needs {}",
                             pdu.num_mask_bytes, pdu.changed_mask.size(), pdu.columns, pdu.rows,
                             (cells + 7) / 8)};
  }
  if (pdu.num_posts < 1 || pdu.num_posts > kMaxEarthMovePosts ||
      static_cast<size_t>(pdu.num_posts) != pdu.delta_mm.size()) {
    return Error{fmt::format("num_posts = {} is outside [1, {}] or disagrees with {} deltas",
                             pdu.num_posts, kMaxEarthMovePosts, pdu.delta_mm.size())};
  }
  if (cells % 8 != 0 && (pdu.changed_mask.back() >> (cells % 8)) != 0) {
    return Error{fmt::format("changed_mask has bits past the {} posts of the rectangle", cells)};
  }
  f.params.post_deltas.reserve(pdu.delta_mm.size());
  size_t next = 0;
  for (int k = 0; k < cells; ++k) {
    if (!((pdu.changed_mask[static_cast<size_t>(k / 8)] >> (k % 8)) & 1u)) continue;
    if (next == pdu.delta_mm.size()) {
      return Error{fmt::format("changed_mask sets more posts than num_posts = {}", pdu.num_posts)};
    }
    const int i = pdu.first_post_i + k % pdu.columns, j = pdu.first_post_j + k / pdu.columns;
    if (i >= kMaxGridPostsPerSide || j >= kMaxGridPostsPerSide) {
      return Error{fmt::format("post ({}, {}) is outside [0, {})", i, j, kMaxGridPostsPerSide)};
    }
    f.params.post_deltas.push_back(
        {static_cast<uint16_t>(i), static_cast<uint16_t>(j), pdu.delta_mm[next++]});
  }
  if (next != pdu.delta_mm.size()) {
    return Error{fmt::format("changed_mask sets {} posts but num_posts = {}", next, pdu.num_posts)};
  }
  return f;
}

Result<DestructPdu> FromDestruct(const dtpdu::destruct_t& pdu) {
  DestructPdu d;
  auto id = IdFromPdu(pdu);
  if (!id) return id.error();
  d.id = id.value();
  auto stamp = StampFromPdu(pdu);
  if (!stamp) return stamp.error();
  d.change = stamp.value();
  auto type = TypeFromPdu(pdu.feature_type);
  if (!type) return type.error();
  d.type = type.value();
  return d;
}

}  // namespace dt

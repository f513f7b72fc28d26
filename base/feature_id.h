// FeatureId: the network-wide identity of a dynamic feature, (site, host, number).
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace dt {

// The thesis's 16-bit feature number is widened to 32 bits (see docs/terrain.md): a node can
// create 4 294 967 295 features before its counter is exhausted, and exhaustion is refused.
struct FeatureId {
  uint16_t site = 0;
  uint16_t host = 0;
  uint32_t number = 0;  // 1, 2, ... per (site, host); 0 means "none yet"

  auto operator<=>(const FeatureId&) const = default;
  std::string ToString() const;  // "site:host:number"
};

// The (site, host) pair that issues feature numbers: one node of the exercise.
struct NodeAddress {
  uint16_t site = 0;
  uint16_t host = 0;
  auto operator<=>(const NodeAddress&) const = default;
  std::string ToString() const;  // "site:host"
};

inline NodeAddress OriginOf(const FeatureId& id) { return {id.site, id.host}; }

}  // namespace dt

// Consecutive numbers of one origin get consecutive hashes (the origin only offsets them), so a
// node's features, numbered 1, 2, ..., fill neighbouring buckets: adding and finding the latest
// ones touches memory that is already cached, where a scrambling hash missed the cache on every
// access of a large table. Origins are spread by a multiplicative offset.
template <>
struct std::hash<dt::FeatureId> {
  size_t operator()(const dt::FeatureId& id) const noexcept {
    const uint64_t origin = (uint64_t{id.site} << 16) | id.host;
    return static_cast<size_t>(uint64_t{id.number} + origin * 0x9E3779B97F4A7C15ull);
  }
};

template <>
struct std::hash<dt::NodeAddress> {
  size_t operator()(const dt::NodeAddress& a) const noexcept {
    return std::hash<uint32_t>{}((uint32_t{a.site} << 16) | a.host);
  }
};

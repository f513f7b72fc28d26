// Encoding and decoding of DIS 7 PDUs (big-endian, layouts in docs/dis.md), and the decoder
// that drops and counts bad input.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "base/enum_list.h"
#include "dis/dis_pdu.h"

namespace dt::dis {

// Encoders fill in the header's PDU type, protocol family and length; the rest of the header is
// taken as given. They throw std::invalid_argument on misuse: a non-finite float, more than 255
// variable parameters or segments.
std::vector<uint8_t> Encode(const EntityStatePdu& pdu);
std::vector<uint8_t> Encode(const PointObjectStatePdu& pdu);
std::vector<uint8_t> Encode(const LinearObjectStatePdu& pdu);
// The same bytes into `out` (resized to the PDU; every byte written), so a sender that keeps
// one buffer allocates nothing per PDU.
void EncodeInto(const EntityStatePdu& pdu, std::vector<uint8_t>& out);

using Pdu = std::variant<EntityStatePdu, PointObjectStatePdu, LinearObjectStatePdu>;

// Why a datagram was dropped: one X(enumerator, value, name) each (base/enum_list.h). Values
// index DecodeCounters::rejected.
#define DT_DECODE_FAILURES(X)                                             \
  /* shorter than a header, or than its PDU type's fixed part */          \
  X(kTooShort, 0, "too short")                                            \
  /* longer than a DIS PDU can be */                                      \
  X(kTooLong, 1, "too long")                                              \
  /* length field differs from the datagram, or from the record counts */ \
  X(kLengthMismatch, 2, "length mismatch")                                \
  /* not DIS 7 (DIS 6 is accepted for Entity State, same layout) */       \
  X(kUnsupportedVersion, 3, "unsupported version")                        \
  /* another exercise ID than the decoder's */                            \
  X(kForeignExercise, 4, "foreign exercise")                              \
  /* a PDU type dynterrain does not read */                               \
  X(kUnsupportedPduType, 5, "unsupported PDU type")                       \
  /* protocol family not the one the PDU type belongs to */               \
  X(kFamilyMismatch, 6, "protocol family mismatch")                       \
  /* a NaN or infinity in a floating-point field */                       \
  X(kNonFinite, 7, "non-finite field")                                    \
  /* a field outside its enumeration (e.g. dead-reckoning algorithm) */   \
  X(kBadField, 8, "bad field")

enum class DecodeFailure : uint8_t { DT_DECODE_FAILURES(DT_ENUM_ENUMERATOR) };

inline constexpr size_t kDecodeFailureCount = 0 DT_DECODE_FAILURES(DT_ENUM_PLUS_ONE);
// Values run 0, 1, 2, ... in the list's order, so a value indexes the counters and the names.
static_assert(EnumValuesRunOn({DT_DECODE_FAILURES(DT_ENUM_VALUE)}, 0));
std::string_view DecodeFailureName(DecodeFailure failure);

struct DecodeError {
  DecodeFailure failure;
  std::string message;  // names the offending values
};

// Either a whole PDU or the reason it was refused: nothing of a refused datagram is kept.
class [[nodiscard]] DecodeResult {
 public:
  DecodeResult(Pdu pdu) : v_(std::move(pdu)) {}              // NOLINT: implicit by design
  DecodeResult(DecodeError error) : v_(std::move(error)) {}  // NOLINT: implicit by design
  bool ok() const { return std::holds_alternative<Pdu>(v_); }
  const Pdu& pdu() const;            // aborts if !ok()
  const DecodeError& error() const;  // aborts if ok()

 private:
  std::variant<Pdu, DecodeError> v_;
};

// Decodes one PDU occupying the whole datagram. exercise_id, when given, refuses PDUs of other
// exercises (before their type is looked at: a foreign exercise's traffic is counted as such).
DecodeResult DecodePdu(std::span<const uint8_t> datagram,
                       std::optional<uint8_t> exercise_id = std::nullopt);

struct DecodeCounters {
  uint64_t entity_state = 0;
  uint64_t point_object_state = 0;
  uint64_t linear_object_state = 0;
  std::array<uint64_t, kDecodeFailureCount> rejected{};
  uint64_t rejected_total() const;
  uint64_t rejected_for(DecodeFailure f) const { return rejected[static_cast<size_t>(f)]; }
};

// One PDU of a datagram that may bundle several (IEEE 1278.2: PDUs concatenated, each framed by
// its own header's length field): its bytes, or why the rest of the datagram cannot be framed.
struct PduFrame {
  std::span<const uint8_t> bytes;    // empty when error is set
  std::optional<DecodeError> error;  // set: the walk over the datagram ends here
};
// The PDU starting at `offset` (< datagram.size()). Refused, ending the walk: fewer bytes left
// than a header (too short), a length field shorter than a header (length mismatch: it frames
// nothing), or one running past the datagram's end (length mismatch: a truncated tail).
PduFrame FrameAt(std::span<const uint8_t> datagram, size_t offset);

// A decoder for one DIS exercise that counts what it accepts and why it drops the rest.
class Decoder {
 public:
  explicit Decoder(uint8_t exercise_id) : exercise_id_(exercise_id) {}
  // One PDU occupying the whole datagram.
  DecodeResult Decode(std::span<const uint8_t> datagram);
  // Every PDU of a datagram bundling one or more, each decoded and counted on its own and given
  // to on_result in order, a refused one too (its neighbours are kept). A tail that cannot be
  // framed is one refusal (FrameAt); a datagram over kMaxPduSize is one (too long).
  template <typename OnResult>
  void DecodeBundle(std::span<const uint8_t> datagram, OnResult&& on_result) {
    if (datagram.size() > kMaxPduSize || datagram.empty()) {
      on_result(Decode(datagram));
      return;
    }
    for (size_t offset = 0; offset < datagram.size();) {
      PduFrame frame = FrameAt(datagram, offset);
      if (frame.error) {
        ++counters_.rejected[static_cast<size_t>(frame.error->failure)];
        on_result(DecodeResult(std::move(*frame.error)));
        return;
      }
      offset += frame.bytes.size();
      on_result(Decode(frame.bytes));
    }
  }
  const DecodeCounters& counters() const { return counters_; }
  uint8_t exercise_id() const { return exercise_id_; }

 private:
  uint8_t exercise_id_;
  DecodeCounters counters_;
};

}  // namespace dt::dis

// IdReservation: where a node records how far its feature numbers may have been issued, so that
// a restarted node never issues one twice (docs/protocol.md, "No ID issued twice").
#pragma once

#include <cstdint>
#include <optional>

#include "base/result.h"

namespace dt {

// A node reserves numbers in blocks before it hands one out; after a crash the next incarnation
// starts past the last reservation, whatever the rest of the exercise remembers. Implementations
// must return from Reserve only once the value survives a crash of the process.
class IdReservation {
 public:
  virtual ~IdReservation() = default;
  // The highest feature number an earlier incarnation reserved; nullopt if nothing was ever
  // recorded (a first start, or the record was lost). An Error is a damaged record: the node
  // refuses to start rather than guess.
  virtual Result<std::optional<int64_t>> Load() = 0;
  // Records that numbers up to `number` may be issued. All or nothing.
  virtual Status Reserve(int64_t number) = 0;
};

// In memory, for simulations: survives the destruction of the replica that used it, as a file
// survives a crashed process. fail makes Reserve fail (a full disk) until cleared.
class MemoryIdReservation final : public IdReservation {
 public:
  Result<std::optional<int64_t>> Load() override { return reserved_; }
  Status Reserve(int64_t number) override {
    if (fail_) return Error{"reserving feature numbers failed (simulated)"};
    reserved_ = number;
    ++writes_;
    return Status::Ok();
  }
  void set_fail(bool fail) { fail_ = fail; }
  std::optional<int64_t> reserved() const { return reserved_; }
  uint64_t writes() const { return writes_; }

 private:
  std::optional<int64_t> reserved_;
  bool fail_ = false;
  uint64_t writes_ = 0;
};

}  // namespace dt

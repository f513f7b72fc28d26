// Result<T>: the value of an operation that can fail at run time for expected reasons.
#pragma once

#include <string>
#include <utility>
#include <variant>

#include "base/demand.h"

namespace dt {

// An expected run-time failure, carried as a message that names the offending values.
struct Error {
  std::string message;
};

// Either a value or an Error. Accessing the wrong alternative is a broken invariant and aborts.
template <typename T>
class [[nodiscard]] Result {
 public:
  // By reference, not by value: a value taken by value was moved twice (into the parameter,
  // then into the variant), which a large T (a feature PDU) pays on every return.
  Result(const T& value) : v_(value) {}          // NOLINT: implicit by design
  Result(T&& value) : v_(std::move(value)) {}    // NOLINT: implicit by design
  Result(Error error) : v_(std::move(error)) {}  // NOLINT: implicit by design

  bool ok() const { return std::holds_alternative<T>(v_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& {
    DT_DEMAND(ok());
    return std::get<T>(v_);
  }
  T& value() & {
    DT_DEMAND(ok());
    return std::get<T>(v_);
  }
  T&& value() && {
    DT_DEMAND(ok());
    return std::get<T>(std::move(v_));
  }
  const Error& error() const {
    DT_DEMAND(!ok());
    return std::get<Error>(v_);
  }

 private:
  std::variant<T, Error> v_;
};

// Success or an Error, for operations with no value.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT: implicit by design
  static Status Ok() { return Status(); }

  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const {
    DT_DEMAND(!ok_);
    return error_;
  }

 private:
  Error error_;
  bool ok_ = true;
};

}  // namespace dt

// DT_DEMAND and DT_UNREACHABLE: checks of broken invariants that say what failed, then abort.
#pragma once

// A broken invariant is a bug, never a consequence of input (docs/conventions.md "Errors": a
// PDU, file, config or command that is wrong gives a Result, a Status or an exception instead).
// The check is never compiled out and evaluates its condition exactly once, so the condition may
// be a call whose effect is wanted.
//
//   DT_DEMAND(n <= size_ - pos_);  // if false, prints "dynterrain: DT_DEMAND(n <= size_ - pos_)
//                                  // failed at <file>:<line> in <function>" to stderr; aborts
//   DT_UNREACHABLE();              // after a switch that returns for every enumerator
//
// The header holds declarations only, no standard headers: the check inlines to one compare and
// a call that is never taken, so it suits hot paths (byte readers, Result::value()).

namespace dt::internal {

// Both write one line to stderr with write(2), allocating nothing, then std::abort().
[[noreturn, gnu::cold, gnu::noinline]] void DemandFailed(const char* condition, const char* file,
                                                         int line, const char* function) noexcept;
[[noreturn, gnu::cold, gnu::noinline]] void UnreachableReached(const char* file, int line,
                                                               const char* function) noexcept;

}  // namespace dt::internal

#define DT_DEMAND(condition)                                                  \
  do {                                                                        \
    if (!(condition)) [[unlikely]] {                                          \
      ::dt::internal::DemandFailed(#condition, __FILE__, __LINE__, __func__); \
    }                                                                         \
  } while (false)

#define DT_UNREACHABLE() ::dt::internal::UnreachableReached(__FILE__, __LINE__, __func__)

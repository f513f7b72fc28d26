// HandleUntil: drives transports until a condition holds, for the tests over real carriers.
#pragma once

#include <chrono>
#include <functional>
#include <initializer_list>

#include "transport/transport.h"

namespace dt::testing {

// Handles each transport in turn until done() or 10 s pass; returns done() (false at once if a
// transport fails).
inline bool HandleUntil(std::initializer_list<Transport*> transports,
                        const std::function<bool()>& done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    for (Transport* t : transports) {
      if (!t->HandleTimeout(20).ok()) return false;
    }
  }
  return done();
}

}  // namespace dt::testing

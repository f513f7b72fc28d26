// Private network namespaces for tests that use real sockets (udpm multicast, DDS).
#pragma once

#include <optional>
#include <string>

namespace dt::testing {

// Re-executes this program (same arguments) inside a new network namespace made with
// `unshare -n`, with lo up, multicast on and a 224.0.0.0/4 route, so multicast traffic never
// leaves the test. Returns at once inside the namespace. If namespaces are unavailable it
// returns and NetnsSkipReason() says why; tests then skip.
void EnterPrivateNetns(int argc, char** argv);

// Why the program is not in a private namespace (nullopt when it is).
std::optional<std::string> NetnsSkipReason();

}  // namespace dt::testing

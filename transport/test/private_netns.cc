#include "transport/test/private_netns.h"

#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

namespace dt::testing {
namespace {

constexpr const char* kInsideVar = "DT_IN_PRIVATE_NETNS";
constexpr const char* kSkipVar = "DT_NETNS_SKIP_REASON";
constexpr const char* kUnshare = "/usr/bin/unshare";
constexpr const char* kSetup =
    "ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo && "
    "exec \"$0\" \"$@\"";

}  // namespace

void EnterPrivateNetns(int argc, char** argv) {
  if (const char* inside = std::getenv(kInsideVar); inside && std::string(inside) == "1") return;
  if (access(kUnshare, X_OK) != 0) {
    setenv(kSkipVar, "/usr/bin/unshare is not installed (util-linux)", 1);
    return;
  }
  // A trial namespace tells "not permitted" (no CAP_SYS_ADMIN, no user namespaces) apart from
  // a failure of the test itself.
  if (std::system("/usr/bin/unshare -n /bin/true >/dev/null 2>&1") != 0 &&
      std::system("/usr/bin/unshare -rn /bin/true >/dev/null 2>&1") != 0) {
    setenv(kSkipVar, "unshare -n is not permitted here (needs root or user namespaces)", 1);
    return;
  }
  const bool as_root = geteuid() == 0;
  std::vector<std::string> args = {"unshare"};
  if (!as_root) args.push_back("-r");  // map to root in a user namespace to configure lo
  for (const char* a : {"-n", "--", "/bin/sh", "-c", kSetup, "/proc/self/exe"}) args.push_back(a);
  // /proc/self/exe is resolved by sh inside the namespace: it is sh itself there, so pass the
  // real path of this program instead.
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) {
    setenv(kSkipVar, "cannot read /proc/self/exe", 1);
    return;
  }
  self[n] = '\0';
  args.back() = self;
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  std::vector<char*> cargs;
  for (auto& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  setenv(kInsideVar, "1", 1);
  execv(kUnshare, cargs.data());
  unsetenv(kInsideVar);
  setenv(kSkipVar, "execv(unshare) failed", 1);
}

std::optional<std::string> NetnsSkipReason() {
  if (const char* r = std::getenv(kSkipVar)) return std::string(r);
  return std::nullopt;
}

}  // namespace dt::testing

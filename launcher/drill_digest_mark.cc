// The drill's digest action (docs/launcher.md "Digest marks"): the digest every live process
// agrees on, kept under a name the first time and compared with the kept one after, so a drill
// can show that a state outlived restarts of every process that held it.
#include <fmt/format.h>

#include "launcher/drill_runner.h"

namespace dt {

void DrillRunner::DigestMark(const DrillAction& a) {
  const double start_s = ElapsedS();
  std::string detail;
  bool agreed = false;
  for (;;) {
    agreed = AgreeOnce(detail);
    if (agreed || ElapsedS() - start_s > a.within_s || Expired()) break;
    if (PollBeside(100)) {
      Check(fmt::format("digest \"{}\"", a.mark), false, "interrupted");
      return;
    }
  }
  const double took_s = ElapsedS() - start_s;
  if (!agreed) {
    Check(fmt::format("digest \"{}\": every live process agrees within {} s", a.mark, a.within_s),
          false, fmt::format("not after {:.1f} s:{}", took_s, detail));
    return;
  }
  const std::string digest = last_digests_.begin()->second;
  const auto kept = marks_.find(a.mark);
  if (kept == marks_.end()) {
    marks_[a.mark] = {digest, start_s};
    Check(fmt::format("digest \"{}\" kept: {} live processes agree", a.mark, last_digests_.size()),
          true, fmt::format("{} after {:.1f} s", digest, took_s));
    return;
  }
  Check(fmt::format("digest \"{}\" as kept at {:.1f} s: {} live processes agree on it", a.mark,
                    kept->second.at_s, last_digests_.size()),
        digest == kept->second.digest,
        fmt::format("{} after {:.1f} s, kept {}", digest, took_s, kept->second.digest));
}

}  // namespace dt

#include "base/demand.h"

#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdlib>

namespace dt::internal {
namespace {

// One line of text in a fixed buffer, written to stderr with a single write(2) where it can be,
// so lines of threads failing at once do not interleave. Nothing is allocated: the heap may be
// what is broken, and the line may be written from a signal handler. Text beyond the buffer is
// cut; the newline always fits.
class Line {
 public:
  Line& operator<<(const char* s) {
    while (*s != '\0' && n_ < kCapacity - 1) buf_[n_++] = *s++;
    return *this;
  }
  Line& operator<<(int v) {
    char digits[12];  // the ten digits of INT_MAX, a sign, a spare
    size_t k = 0;
    // Negated into an unsigned, so INT_MIN does not overflow.
    unsigned u = v < 0 ? 0u - static_cast<unsigned>(v) : static_cast<unsigned>(v);
    do {
      digits[k++] = static_cast<char>('0' + u % 10);
      u /= 10;
    } while (u != 0);
    if (v < 0) digits[k++] = '-';
    while (k > 0 && n_ < kCapacity - 1) buf_[n_++] = digits[--k];
    return *this;
  }
  void WriteToStderr() {
    buf_[n_++] = '\n';
    size_t done = 0;
    while (done < n_) {
      const ssize_t w = write(STDERR_FILENO, buf_ + done, n_ - done);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) return;  // nowhere to say it: the abort still happens
      done += static_cast<size_t>(w);
    }
  }

 private:
  static constexpr size_t kCapacity = 2048;
  char buf_[kCapacity];
  size_t n_ = 0;
};

}  // namespace

void DemandFailed(const char* condition, const char* file, int line,
                  const char* function) noexcept {
  Line out;
  out << "dynterrain: DT_DEMAND(" << condition << ") failed at " << file << ":" << line << " in "
      << function;
  out.WriteToStderr();
  std::abort();
}

void UnreachableReached(const char* file, int line, const char* function) noexcept {
  Line out;
  out << "dynterrain: DT_UNREACHABLE() reached at " << file << ":" << line << " in " << function;
  out.WriteToStderr();
  std::abort();
}

}  // namespace dt::internal

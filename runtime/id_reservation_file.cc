#include "runtime/id_reservation_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include <fmt/format.h>
#include <xxhash.h>

#include "pdu/pdu_type.h"

namespace dt {
namespace {

constexpr std::string_view kMagic = "dynterrain-ids";
constexpr int kVersion = 1;
constexpr size_t kMaxFileBytes = 256;  // one short line

std::string Body(NodeAddress a, int64_t number) {
  return fmt::format("{} {} {} {}", kMagic, kVersion, a.ToString(), number);
}

uint64_t Checksum(std::string_view body) { return XXH3_64bits(body.data(), body.size()); }

std::string Errno() { return std::strerror(errno); }

}  // namespace

IdReservationFile::IdReservationFile(std::filesystem::path path, NodeAddress address)
    : path_(std::move(path)), address_(address) {}

Result<std::optional<int64_t>> IdReservationFile::Load() {
  // O_NONBLOCK: a FIFO put in its place must not freeze the start.
  const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    if (errno == ENOENT) return std::optional<int64_t>{};
    return Error{
        fmt::format("cannot open the feature number reservation {}: {}", path_.string(), Errno())};
  }
  struct stat st {};
  std::string text;
  std::string problem;
  if (::fstat(fd, &st) != 0) {
    problem = "cannot stat it: " + Errno();
  } else if (!S_ISREG(st.st_mode)) {
    problem = "it is not a regular file";
  } else if (static_cast<size_t>(st.st_size) > kMaxFileBytes) {
    problem = fmt::format("it has {} bytes, more than {}", st.st_size, kMaxFileBytes);
  } else {
    text.resize(static_cast<size_t>(st.st_size));
    const ssize_t n = ::read(fd, text.data(), text.size());
    if (n != static_cast<ssize_t>(text.size())) problem = "cannot read it: " + Errno();
  }
  ::close(fd);
  auto damaged = [&](const std::string& why) {
    return Error{fmt::format(
        "the feature number reservation {} is damaged ({}); the node will not start, since it "
        "could reissue a feature ID. If this node's numbers cannot be in the exercise any more "
        "(a new exercise), delete the file",
        path_.string(), why)};
  };
  if (!problem.empty()) return damaged(problem);
  if (text.empty() || text.back() != '\n') return damaged("truncated");
  text.pop_back();
  const size_t last_space = text.rfind(' ');
  if (last_space == std::string::npos) return damaged("no checksum");
  const std::string body = text.substr(0, last_space);
  const std::string sum = text.substr(last_space + 1);
  if (fmt::format("{:016x}", Checksum(body)) != sum) return damaged("checksum mismatch");
  char magic[32] = {};
  int version = 0;
  unsigned site = 0, host = 0;
  long long number = -1;
  char tail = 0;
  if (std::sscanf(body.c_str(), "%31s %d %u:%u %lld%c", magic, &version, &site, &host, &number,
                  &tail) != 5 ||
      magic != kMagic) {
    return damaged("not a reservation line");
  }
  if (version != kVersion)
    return damaged(fmt::format("version {}, expected {}", version, kVersion));
  if (site != address_.site || host != address_.host) {
    return damaged(
        fmt::format("written for node {}:{}, this node is {}", site, host, address_.ToString()));
  }
  if (number < 0 || number > kMaxSerial) return damaged(fmt::format("number {}", number));
  return std::optional<int64_t>{number};
}

Status IdReservationFile::Reserve(int64_t number) {
  const std::string body = Body(address_, number);
  const std::string line = fmt::format("{} {:016x}\n", body, Checksum(body));
  const std::filesystem::path tmp = path_.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return Error{fmt::format("cannot write {}: {}", tmp.string(), Errno())};
  const bool written = ::write(fd, line.data(), line.size()) == static_cast<ssize_t>(line.size());
  const std::string write_error = written ? "" : Errno();
  const bool synced = written && ::fsync(fd) == 0;
  ::close(fd);
  if (!synced) {
    ::unlink(tmp.c_str());
    return Error{fmt::format("cannot write {}: {}", tmp.string(), written ? Errno() : write_error)};
  }
  if (::rename(tmp.c_str(), path_.c_str()) != 0) {
    const std::string e = Errno();
    ::unlink(tmp.c_str());
    return Error{fmt::format("cannot replace {}: {}", path_.string(), e)};
  }
  // The rename is durable only once the directory is.
  const std::filesystem::path dir = path_.has_parent_path() ? path_.parent_path() : ".";
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    const bool ok = ::fsync(dfd) == 0;
    ::close(dfd);
    if (!ok) return Error{fmt::format("cannot sync the directory {}: {}", dir.string(), Errno())};
  }
  return Status::Ok();
}

}  // namespace dt

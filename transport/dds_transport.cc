#include "transport/dds_transport.h"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <charconv>
#include <cstdlib>
#include <stdexcept>

#include <dds/dds.h>
#include <fmt/format.h>

#include "base/demand.h"
#include "log/log.h"
#include "transport/dds_codec.h"

namespace dt {
namespace {

size_t IndexOf(PduType type) {
  for (size_t i = 0; i < kAllPduTypes.size(); ++i) {
    if (kAllPduTypes[i] == type) return i;
  }
  DT_UNREACHABLE();  // every PduType is in kAllPduTypes
}

std::runtime_error DdsError(const std::string& what, dds_return_t rc) {
  return std::runtime_error(fmt::format("DDS: {}: {}", what, dds_strretcode(rc)));
}

void OnDataAvailable(dds_entity_t /*reader*/, void* arg) {
  const int fd = *static_cast<const int*>(arg);
  const uint64_t one = 1;
  [[maybe_unused]] ssize_t w = write(fd, &one, sizeof one);
}

// Reliable, keep-all, volatile, and a writer never waits for room in its history: when a reader
// has not acknowledged enough (a dead one not yet unmatched), dds_write returns Timeout at once
// and the PDU is not written, so the caller's loop goes on (RetryingTransport queues it).
// Durable feature topics: transient-local, and a writer keeps only the latest sample of each
// feature (instance), which it also gives to every reader that joins later.
enum class Role { kTopic, kWriter, kReader };
dds_qos_t* MakeQos(bool durable_feature, Role role) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, 0);
  if (durable_feature && role == Role::kWriter) {
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
  } else {
    dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
  }
  dds_qset_durability(qos,
                      durable_feature ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  return qos;
}

bool IsFeatureType(PduType type) {
  return type == PduType::kConstruct || type == PduType::kUpdate || type == PduType::kDestruct ||
         type == PduType::kEarthMove;
}

}  // namespace

std::string DomainConfig(const DdsConfig& config) {
  std::string uri = std::string(kDdsDomainDefaults);
  if (!config.config_file.empty()) {
    uri += ",file://" + config.config_file;
  } else if (const char* env = std::getenv("CYCLONEDDS_URI"); env != nullptr && *env != '\0') {
    uri += ",";
    uri += env;
  }
  return uri;
}

DdsConfig ParseDdsUrl(std::string_view url) {
  constexpr std::string_view kScheme = "dds://";
  if (url.substr(0, kScheme.size()) != kScheme) {
    throw std::invalid_argument(fmt::format("'{}' is not a dds:// URL", url));
  }
  std::string_view rest = url.substr(kScheme.size());
  std::string_view query;
  if (auto q = rest.find('?'); q != std::string_view::npos) {
    query = rest.substr(q + 1);
    rest = rest.substr(0, q);
  }
  DdsConfig config;
  if (!rest.empty()) {
    auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), config.domain_id);
    if (ec != std::errc() || end != rest.data() + rest.size() || config.domain_id > 230) {
      throw std::invalid_argument(
          fmt::format("'{}': the domain must be a number in [0, 230], got '{}'", url, rest));
    }
  }
  // Options: config=<file>, durable=0|1, separated by '&'.
  for (bool more = !query.empty(); more;) {
    const size_t amp = query.find('&');
    const std::string_view option = query.substr(0, amp);
    more = amp != std::string_view::npos;
    if (more) query = query.substr(amp + 1);
    constexpr std::string_view kConfig = "config=";
    if (option.substr(0, kConfig.size()) == kConfig && option.size() > kConfig.size()) {
      config.config_file = std::string(option.substr(kConfig.size()));
    } else if (option == "durable=1" || option == "durable=0") {
      config.durable_features = option == "durable=1";
    } else {
      throw std::invalid_argument(fmt::format(
          "'{}': options are config=<file> and durable=0|1 (joined by &), got '{}'", url, option));
    }
  }
  return config;
}

DdsTransport::DdsTransport(DdsConfig config, uint8_t exercise_id)
    : config_(std::move(config)), exercise_id_(exercise_id) {
  event_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (event_fd_ < 0) throw std::runtime_error("DDS: eventfd failed");
  if (!config_.config_file.empty() && access(config_.config_file.c_str(), R_OK) != 0) {
    close(event_fd_);
    throw std::runtime_error(
        fmt::format("DDS: cannot read the configuration '{}'", config_.config_file));
  }
  const std::string domain_config = DomainConfig(config_);
  const dds_entity_t d = dds_create_domain(config_.domain_id, domain_config.c_str());
  // Another transport of this process may have created the domain already: share it.
  if (d > 0) domain_ = d;
  participant_ = dds_create_participant(config_.domain_id, nullptr, nullptr);
  if (participant_ < 0) {
    const dds_return_t rc = participant_;
    if (domain_ > 0) dds_delete(domain_);
    close(event_fd_);
    throw DdsError(fmt::format("creating a participant in domain {}", config_.domain_id), rc);
  }
  try {
    for (size_t i = 0; i < kAllPduTypes.size(); ++i) {
      const PduType type = kAllPduTypes[i];
      const std::string name = ChannelName(exercise_id_, type);
      const bool durable = Durable(type);
      auto& t = types_[i];
      dds_qos_t* qos = MakeQos(durable, Role::kTopic);
      t.topic =
          dds_create_topic(participant_, dds_codec::Descriptor(type), name.c_str(), qos, nullptr);
      dds_delete_qos(qos);
      if (t.topic < 0) throw DdsError("creating topic " + name, t.topic);
      qos = MakeQos(durable, Role::kWriter);
      t.writer = dds_create_writer(participant_, t.topic, qos, nullptr);
      dds_delete_qos(qos);
      if (t.writer < 0) throw DdsError("creating a writer on " + name, t.writer);
    }
  } catch (...) {
    dds_delete(participant_);
    if (domain_ > 0) dds_delete(domain_);
    close(event_fd_);
    throw;
  }
}

bool DdsTransport::Durable(PduType type) const {
  return config_.durable_features && IsFeatureType(type);
}

DdsTransport::~DdsTransport() {
  // Deleting the participant deletes its readers and waits for running listeners, so the
  // eventfd is closed only afterwards.
  dds_delete(participant_);
  if (domain_ > 0) dds_delete(domain_);
  close(event_fd_);
}

std::string DdsTransport::Url() const {
  std::string url = fmt::format("dds://{}", config_.domain_id);
  if (!config_.config_file.empty()) url += "?config=" + config_.config_file;
  if (config_.durable_features) url += config_.config_file.empty() ? "?durable=1" : "&durable=1";
  return url;
}

Status DdsTransport::Publish(PduType type, std::span<const uint8_t> bytes) {
  if (bytes.size() > kMaxPduBytes) {
    return Error{fmt::format("{} PDU of {} bytes exceeds the {}-byte single-datagram limit",
                             PduTypeName(type), bytes.size(), kMaxPduBytes)};
  }
  if (Status s = dds_codec::Write(type, types_[IndexOf(type)].writer, bytes); !s) {
    return Error{fmt::format("DDS write on {} failed: {}", ChannelName(exercise_id_, type),
                             s.error().message)};
  }
  return Status::Ok();
}

void DdsTransport::Subscribe(PduType type, Handler handler) {
  auto& t = types_[IndexOf(type)];
  if (t.reader == 0) {
    dds_qos_t* qos = MakeQos(Durable(type), Role::kReader);
    dds_listener_t* listener = dds_create_listener(nullptr);
    dds_lset_data_available_arg(listener, OnDataAvailable, &event_fd_, true);
    t.reader = dds_create_reader(participant_, t.topic, qos, listener);
    dds_delete_listener(listener);
    dds_delete_qos(qos);
    if (t.reader < 0) {
      const dds_return_t rc = t.reader;
      t.reader = 0;
      throw DdsError("creating a reader on " + ChannelName(exercise_id_, type), rc);
    }
  }
  t.handlers.push_back(std::move(handler));
}

int DdsTransport::TakeAll(PduType type, PerType& t) {
  constexpr size_t kBatch = 64;
  int dispatched = 0;
  for (;;) {
    void* samples[kBatch] = {};
    dds_sample_info_t infos[kBatch];
    const dds_return_t n = dds_take(t.reader, samples, infos, kBatch, kBatch);
    if (n <= 0) break;
    for (dds_return_t i = 0; i < n; ++i) {
      if (!infos[i].valid_data) continue;
      if (!dds_codec::Read(type, samples[i], bytes_)) {
        // Only a writer outside dynterrain can produce such a sample: nothing to hand on.
        if (undecodable_++ % 1000 == 0) {
          DT_LOG_WARN("DDS: dropped an inconsistent {} sample ({} so far)",
                      ChannelName(exercise_id_, type), undecodable_);
        }
        continue;
      }
      const std::span<const uint8_t> bytes(bytes_);
      ++dispatched;
      for (size_t h = 0; h < t.handlers.size(); ++h) {
        [&]() noexcept { t.handlers[h](bytes); }();
      }
    }
    dds_return_loan(t.reader, samples, n);
    if (static_cast<size_t>(n) < kBatch) break;
  }
  return dispatched;
}

int DdsTransport::MatchedReaders(PduType type) const {
  dds_publication_matched_status_t st{};
  if (dds_get_publication_matched_status(types_[IndexOf(type)].writer, &st) != DDS_RETCODE_OK) {
    return -1;
  }
  return static_cast<int>(st.current_count);
}

bool DdsTransport::WaitForReaders(PduType type, int readers, int timeout_ms) {
  const dds_entity_t writer = types_[IndexOf(type)].writer;
  dds_set_status_mask(writer, DDS_PUBLICATION_MATCHED_STATUS);
  const dds_entity_t waitset = dds_create_waitset(participant_);
  if (waitset < 0) return false;
  dds_waitset_attach(waitset, writer, writer);
  const dds_time_t deadline = dds_time() + DDS_MSECS(timeout_ms);
  bool matched = false;
  for (;;) {
    dds_publication_matched_status_t st{};
    if (dds_get_publication_matched_status(writer, &st) == DDS_RETCODE_OK &&
        st.current_count >= static_cast<uint32_t>(readers)) {
      matched = true;
      break;
    }
    if (dds_waitset_wait_until(waitset, nullptr, 0, deadline) <= 0 && dds_time() >= deadline) {
      break;
    }
  }
  dds_delete(waitset);
  return matched;
}

Result<int> DdsTransport::HandleTimeout(int timeout_ms) {
  pollfd p{event_fd_, POLLIN, 0};
  const int rc = poll(&p, 1, timeout_ms);
  if (rc < 0 && errno != EINTR) return Error{fmt::format("DDS: poll failed (errno {})", errno)};
  uint64_t count;
  [[maybe_unused]] ssize_t r = read(event_fd_, &count, sizeof count);
  int dispatched = 0;
  for (size_t i = 0; i < kAllPduTypes.size(); ++i) {
    if (types_[i].reader != 0) dispatched += TakeAll(kAllPduTypes[i], types_[i]);
  }
  return dispatched;
}

}  // namespace dt

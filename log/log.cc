#include "log/log.h"

#include <memory>
#include <mutex>
#include <stdexcept>

#include <spdlog/sinks/stdout_sinks.h>

namespace dt::log {
namespace {

std::mutex& InitMutex() {
  static std::mutex m;
  return m;
}

std::shared_ptr<spdlog::logger>& Instance() {
  static std::shared_ptr<spdlog::logger> logger;
  return logger;
}

std::shared_ptr<spdlog::logger> Make(std::string_view name, spdlog::level::level_enum level) {
  // Log lines go to stderr so stdout stays free for a program's own output (reports, status).
  auto logger = std::make_shared<spdlog::logger>(std::string(name),
                                                 std::make_shared<spdlog::sinks::stderr_sink_mt>());
  logger->set_pattern("%Y-%m-%dT%H:%M:%S.%e %l [%n] %v");
  logger->set_level(level);
  logger->flush_on(spdlog::level::info);
  return logger;
}

}  // namespace

void Init(std::string_view process_name, std::string_view level) {
  const auto parsed = spdlog::level::from_str(std::string(level));
  if (parsed == spdlog::level::off && level != "off") {
    throw std::invalid_argument("unknown log level '" + std::string(level) +
                                "' (debug, info, warn, error, off)");
  }
  std::lock_guard lock(InitMutex());
  Instance() = Make(process_name, parsed);
}

spdlog::logger& Logger() {
  std::lock_guard lock(InitMutex());
  auto& logger = Instance();
  if (!logger) logger = Make("dynterrain", spdlog::level::info);
  return *logger;
}

}  // namespace dt::log

// Logging: the one entry point for every process's log lines, each carrying the process's name.
#pragma once

#include <string>
#include <string_view>

#include <spdlog/spdlog.h>

namespace dt::log {

// Names the process ("node-2", "server") and sets the level ("debug", "info", "warn", "error").
// Every line then reads "<time> <level> [<name>] <message>". Throws std::invalid_argument for an
// unknown level. Safe to call again (tests), which replaces the previous settings.
void Init(std::string_view process_name, std::string_view level = "info");

// The process's logger; usable before Init (then named "dynterrain").
spdlog::logger& Logger();

// A phrase in every line about clock skew between hosts (pdu/clock_watch.h), for tools that pick
// those lines out of a process's output: dt_launch and dt_drill show a child's latest one when it
// never becomes ready (launcher/supervisor.h).
inline constexpr std::string_view kClockSkewMarker = "clock skew";
// A phrase in every line about a member on another ground than the exercise's (engine/replica.h
// ground_refused), picked out the same way.
inline constexpr std::string_view kGroundMismatchMarker = "ground mismatch";

}  // namespace dt::log

// fmt-style logging: DT_LOG_INFO("applied {} PDUs", n).
#define DT_LOG_DEBUG(...) ::dt::log::Logger().debug(__VA_ARGS__)
#define DT_LOG_INFO(...) ::dt::log::Logger().info(__VA_ARGS__)
#define DT_LOG_WARN(...) ::dt::log::Logger().warn(__VA_ARGS__)
#define DT_LOG_ERROR(...) ::dt::log::Logger().error(__VA_ARGS__)

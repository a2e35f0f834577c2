#pragma once
/// \file Logging sink. The library never prints (DESIGN.md §3.8): it hands messages to a
/// callback that the caller (usually the CLI) installs.

#include <functional>
#include <string>

namespace viaduct {

enum class LogLevel { debug, info, warning };

/// Receives library messages. An empty function discards them.
using LogSink = std::function<void(LogLevel, const std::string&)>;

/// Progress of long work: `done` of `total` units finished. Called from worker threads, but
/// never concurrently (calls are serialised by the caller of the sink).
using ProgressSink = std::function<void(std::size_t done, std::size_t total)>;

}  // namespace viaduct

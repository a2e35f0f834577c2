#pragma once
/// \file Traffic mix files: the trains of a line a day at their speeds (fatigue, issue #42).

#include <string>

#include "viaduct/study/fatigue.hpp"

namespace viaduct::io {

/// A traffic mix file (data/trains/fatigue/mix-*.toml): `title`, then [[trains]] tables of `file`
/// (a train file, relative to the mix file), `per_day` (>= 0) and `speed_kmh` (> 0). InputError
/// with file, line and key for a missing, unknown or invalid key or a train file that is not there.
study::TrafficMix read_traffic_mix(const std::string& path);

}  // namespace viaduct::io

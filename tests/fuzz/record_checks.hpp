#pragma once
#include <cmath>

#include "harness.hpp"
#include "viaduct/io/record.hpp"

namespace fuzz {
inline void check_record(const viaduct::io::Record& r) {
  require(r.fs_hz > 0 && std::isfinite(r.fs_hz), "a positive, finite rate");
  require(std::isfinite(r.t0_s), "a finite start");
  require(r.channels.size() == r.units.size() && static_cast<viaduct::Index>(r.channels.size()) == r.data.cols(),
          "one name and unit per column");
  require(r.data.rows() >= 1, "at least one sample");
  require(r.data.allFinite(), "no NaN or infinite sample");
}
}  // namespace fuzz

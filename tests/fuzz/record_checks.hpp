#pragma once
#include <cmath>

#include "harness.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"

namespace fuzz {
inline void check_record(const viaduct::io::Record& r) {
  require(r.fs_hz > 0 && std::isfinite(r.fs_hz), "a positive, finite rate");
  require(std::isfinite(r.t0_s), "a finite start");
  require(r.channels.size() == r.units.size() && static_cast<viaduct::Index>(r.channels.size()) == r.data.cols(),
          "one name and unit per column");
  require(r.data.rows() >= 1, "at least one sample");
  // Missing samples stay NaN in their own channel (issue #39); never an infinity, and what a
  // command takes of a channel (valid_span) is finite or a clear error.
  require(!r.data.array().isInf().any(), "no infinite sample");
  for (std::size_t c = 0; c < r.channels.size(); ++c) {
    try {
      const viaduct::io::Record u = viaduct::io::valid_span(r, {c}, "fuzz", nullptr);
      require(u.data.col(static_cast<viaduct::Index>(c)).allFinite() && u.n_samples() >= 2, "a channel's valid span is finite");
    } catch (const viaduct::InputError&) {
    }
  }
}
}  // namespace fuzz

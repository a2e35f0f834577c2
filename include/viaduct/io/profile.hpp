#pragma once
/// \file Measured rail profiles (issue #21 part 3): a CSV of positions and vertical levels.

#include <string>

#include "viaduct/load/irregularity.hpp"

namespace viaduct::io {

/// A profile as a track recording car or a survey writes it: a header naming the position and
/// the level, each with its unit (`x_m,z_mm`, `x [m],level [mm]`; m, mm, cm or um), then one row
/// per point, comma separated, '#' lines skipped. The positions must increase by one step (each
/// within 1 % of a step of its place: a survey's rounding); the step and the first position become the profile's dx and
/// x0, the levels are converted to metres. InputError naming file and line for a missing or
/// malformed header, a unit that is not a length, a cell that is not a number, a position out of
/// order or off the step (resample first), and fewer than 4 points.
load::RailProfile read_rail_profile(const std::string& path);

}  // namespace viaduct::io

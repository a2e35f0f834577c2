#pragma once
/// \file Traffic mix files: the trains of a line a day at their speeds (fatigue, issue #42).

#include <string>
#include <vector>

#include "viaduct/io/results.hpp"
#include "viaduct/study/fatigue.hpp"

namespace viaduct::io {

/// A traffic mix file (data/trains/fatigue/mix-*.toml): `title`, then [[trains]] tables of `file`
/// (a train file, relative to the mix file), `per_day` (>= 0), `speed_kmh` (> 0) and an optional
/// `name` (default: the file's stem). A name listed more than once (one type at several speeds)
/// gets " at <speed> km/h"; the same name at the same speed twice is refused. InputError with
/// file, line and key for a missing, unknown or invalid key or a train file that is not there.
study::TrafficMix read_traffic_mix(const std::string& path);

/// damage.csv of a mix (`viaduct fatigue --mix`, `viaduct.fatigue_mix`): per train its name,
/// per_day, speed_kmh, curve, cycles, damaging_cycles, max_range_mpa (factored),
/// damage_per_passage, damage_per_year, share_of_year, equivalent_range_2e6_mpa (of a year's
/// damage), years_to_d1 and message (why it failed; its numbers empty); a last row "total".
std::vector<TableColumn> fatigue_mix_damage_columns(const study::MixDamage& d, const study::FatigueCount& f);
/// cycles.csv of a mix: train, range_low_mpa, range_high_mpa, mean_low_mpa, mean_high_mpa, count
/// (one passage, without the partial factors).
std::vector<TableColumn> fatigue_mix_cycle_columns(const study::MixDamage& d, const study::FatigueCount& f);
/// The digits of the fatigue tables' numbers.
constexpr int kFatigueDigits = 8;

}  // namespace viaduct::io

// viaduct fatigue: rainflow cycles and Miner damage of a record's stress, strain or moment
// channels, or of a traffic mix run over a scenario's model (issue #42; docs/fatigue.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "cli.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/io/traffic_mix.hpp"
#include "viaduct/signal/rainflow.hpp"
#include "viaduct/study/fatigue.hpp"

namespace viaduct::cli {

namespace {

struct FatigueOptions {
  std::vector<std::string> channels;
  std::optional<double> detail_mpa;     ///< EN 1993-1-9 detail category
  std::optional<double> delta_c_mpa;    ///< a user curve: its Δσ_C at 2e6 …
  double m1 = 3.0, m2 = 5.0;            ///< … and slopes
  double youngs_modulus_pa = 210e9;     ///< strain channels: σ = E ε (structural steel, EN 1993-1-1 3.2.6)
  std::optional<double> section_modulus_m3;  ///< moment channels: σ = M / W
  double gamma_ff = 1.0, gamma_mf = 1.0;
  std::string method = "three-point";
  double hysteresis_mpa = 0.0;
  double range_bin_mpa = 1.0, mean_bin_mpa = 5.0;
  std::optional<std::string> mix;  ///< a traffic mix file: the positional is then a scenario
};

// [Pa] per unit `u` of channel `name` (study::stress_per_unit with the options' E and W).
double unit_to_pa(const std::string& name, const std::string& u, const FatigueOptions& k) {
  return study::stress_per_unit(name, u, k.youngs_modulus_pa, k.section_modulus_m3);
}

double to_pa(const io::Record& r, std::size_t ch, const FatigueOptions& k) { return unit_to_pa(r.channels[ch], r.units[ch], k); }

study::FatigueCount count_of(const FatigueOptions& k) {
  study::FatigueCount f;
  f.curve = study::sn_curve(k.detail_mpa, k.delta_c_mpa, k.m1, k.m2);
  f.gamma_ff = k.gamma_ff;
  f.gamma_mf = k.gamma_mf;
  f.method = signal::rainflow_method(k.method, "--method");
  f.hysteresis_mpa = k.hysteresis_mpa;
  f.range_bin_mpa = k.range_bin_mpa;
  f.mean_bin_mpa = k.mean_bin_mpa;
  return f;
}

void check_options(const FatigueOptions& k) {
  auto positive = [](double v, const char* key) {
    if (!(v > 0.0) || !std::isfinite(v)) throw InputError(std::string(key) + " = " + format_number(v, 6) + ": violated constraint > 0");
  };
  positive(k.youngs_modulus_pa, "--youngs-modulus-pa");
  if (k.section_modulus_m3) positive(*k.section_modulus_m3, "--section-modulus-m3");
  positive(k.range_bin_mpa, "--range-bin-mpa");
  positive(k.mean_bin_mpa, "--mean-bin-mpa");
  if (!(k.hysteresis_mpa >= 0.0)) throw InputError("--hysteresis-mpa must be >= 0");
  signal::rainflow_method(k.method, "--method");
}

std::string fatigue_cell(double v) { return io::table_cell(v, io::kFatigueDigits); }

// cycles.csv's rows of one history (its name first).
void add_cycle_rows(const std::string& name, const study::CountedHistory& h, const study::FatigueCount& f,
                    std::vector<std::vector<std::string>>& rows) {
  for (const auto& [b, n] : h.bins)
    rows.push_back({name, fatigue_cell(b.first * f.range_bin_mpa), fatigue_cell((b.first + 1) * f.range_bin_mpa), fatigue_cell(b.second * f.mean_bin_mpa),
                    fatigue_cell((b.second + 1) * f.mean_bin_mpa), fatigue_cell(n)});
}

std::string years_cell(double years) { return std::isfinite(years) ? fatigue_cell(years) : ""; }

// One channel: its cycles binned (range × mean, MPa) and its damage row.
void count_channel(const io::Record& in, std::size_t ch, const FatigueOptions& k, const study::FatigueCount& f,
                   std::vector<std::vector<std::string>>& cycle_rows, std::vector<std::vector<std::string>>& damage_rows,
                   std::vector<std::string>& warnings, bool quiet) {
  const study::CountedHistory h = study::count_history(Vector(in.data.col(static_cast<Index>(ch))), to_pa(in, ch, k), f);
  const study::MinerSum& miner = h.miner;
  add_cycle_rows(in.channels[ch], h, f, cycle_rows);
  const std::string unit_slip = study::stress_range_warning("channel " + in.channels[ch], miner.max_range_pa);
  if (!unit_slip.empty()) warnings.push_back(unit_slip);
  const double duration = static_cast<double>(in.n_samples() - 1) / in.fs_hz;
  const double years = miner.damage > 0.0 ? duration / miner.damage / (365.25 * 86400.0) : std::numeric_limits<double>::infinity();
  damage_rows.push_back({in.channels[ch], f.curve.name, fatigue_cell(k.gamma_ff), fatigue_cell(k.gamma_mf), fatigue_cell(miner.cycles), fatigue_cell(miner.damaging),
                         fatigue_cell(miner.max_range_pa * 1e-6), fatigue_cell(miner.damage), fatigue_cell(study::equivalent_range_2e6(miner.damage, f.curve) * 1e-6),
                         fatigue_cell(duration), years_cell(years)});
  if (!quiet)
    std::printf("%-22s %.1f cycles (%.1f above the cut-off), largest range %.4g MPa; D = %.4g (%s years to D = 1 at this record's rate)\n",
                in.channels[ch].c_str(), miner.cycles, miner.damaging, miner.max_range_pa * 1e-6, miner.damage,
                std::isfinite(years) ? format_number(years, 4).c_str() : "no");
}

int run_records(const Common& o, const FatigueOptions& k, const study::FatigueCount& f) {
  if (!o.set.empty() || !o.unset.empty())
    throw InputError("--set and --unset change scenario keys: a record has none (with --mix the positional is a scenario)");
  const io::Record whole = read_record(o.scenario, o);
  const auto chans = selected(whole, k.channels);
  for (std::size_t ch : chans) to_pa(whole, ch, k);  // every channel's unit checked before counting
  std::vector<std::vector<std::string>> cycle_rows, damage_rows;
  std::vector<std::string> warnings;
  // Each channel over its own valid span: a gap in one channel cuts no other (usable() warns).
  for (std::size_t ch : chans) count_channel(usable(whole, {ch}, o), ch, k, f, cycle_rows, damage_rows, warnings, o.quiet);
  print_warnings("fatigue", warnings);
  make_out_dir(o.out);
  io::write_table_csv(o.out + "/cycles.csv", {"channel", "range_low_mpa", "range_high_mpa", "mean_low_mpa", "mean_high_mpa", "count"},
                      cycle_rows);
  write_table_outputs(o, "damage.csv",
                      {"channel", "curve", "gamma_ff", "gamma_mf", "cycles", "damaging_cycles", "max_range_mpa", "damage",
                       "equivalent_range_2e6_mpa", "duration_s", "years_to_d1_at_record_rate"},
                      damage_rows, warnings);
  if (!o.quiet) std::printf("wrote %s/cycles.csv, damage.csv\n", o.out.c_str());
  return ok;
}

// `s` as a TOML string, escaped as the scenario's strings are (a mix's title is the user's text).
std::string toml_text(const std::string& s) {
  io::Value v;
  v.type = io::ValueType::string;
  v.s = s;
  return v.to_toml();
}

// --mix: every train of the mix over the scenario's model at its speed, the station's stress
// history counted; damage per passage, per year of the mix and years to D = 1.
int run_mix(const Common& o, const FatigueOptions& k, const study::FatigueCount& f) {
  const auto t0 = std::chrono::steady_clock::now();
  const io::FlatScenario flat = load_scenario(o);
  study::Scenario sc = io::to_scenario(flat);
  const study::TrafficMix mix = io::read_traffic_mix(*k.mix);
  if (k.channels.size() != 1)
    throw InputError("--mix: give one --channel, a deck station's moment or strain: <station>_moment or <station>_strain");
  const study::PreparedModel pm = study::prepare_model(sc, /*rail_outputs=*/true, /*with_load_effects=*/true);
  const std::size_t effect = study::fatigue_effect(pm, k.channels[0]);
  const std::string& name = pm.effects[effect].name;
  const double to_pa = unit_to_pa(name, name.substr(name.rfind('_') + 1), k);
  const study::MixDamage d =
      study::traffic_damage(pm, sc.settings, effect, to_pa, mix, f, o.threads, progress_printer("fatigue", o.quiet, "trains"));
  io::Manifest man = start_manifest(o, "fatigue", {o.scenario, *k.mix});
  double largest = 0.0;
  for (const study::TrainDamage& t : d.trains) {
    if (!t.passage) man.warnings.push_back(t.name + " failed: " + t.error + " (the mix's damage lacks it)");
    else largest = std::max(largest, t.passage->miner.max_range_pa);
  }
  const std::string unit_slip = study::stress_range_warning(name + " over the mix's trains", largest);
  if (!unit_slip.empty()) man.warnings.push_back(unit_slip);
  make_out_dir(o.out);
  io::write_table_columns_csv(o.out + "/cycles.csv", io::fatigue_mix_cycle_columns(d, f), io::kFatigueDigits);
  io::write_table_columns_csv(o.out + "/damage.csv", io::fatigue_mix_damage_columns(d, f), io::kFatigueDigits);
  print_warnings("fatigue", man.warnings);
  man.extra = {{"mix", toml_text(mix.title)}, {"channel", toml_text(name)}, {"curve", toml_text(f.curve.name)}};
  man.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  io::write_manifest(o.out + "/manifest.toml", man, flat);
  if (!o.quiet) {
    for (const study::TrainDamage& t : d.trains)
      if (t.passage)
        std::printf("%-10s %6.4g a day at %5.1f km/h: largest range %.4g MPa, D = %.4g a passage, %.4g a year\n", t.name.c_str(), t.per_day,
                    t.speed * 3.6, t.passage->miner.max_range_pa * 1e-6, t.passage->miner.damage, t.per_year);
    std::printf("%s at %s: D = %.4g a year (%s years to D = 1), %s; wrote %s/cycles.csv, damage.csv\n", mix.title.c_str(), name.c_str(), d.per_year,
                std::isfinite(d.years_to_d1()) ? format_number(d.years_to_d1(), 4).c_str() : "no damage: no", f.curve.name.c_str(), o.out.c_str());
  }
  return d.n_failed == 0 ? ok : runtime_failure;
}

}  // namespace

Command fatigue_command() {
  Command c = record_command("fatigue", "RECORD|SCENARIO", "rainflow cycles and Miner damage of stress, strain or moment channels (cycles.csv, damage.csv)");
  const auto declare = [](po::options_description& d, FatigueOptions& k) {
    add_channel_option(d, k.channels);
    d.add_options()("detail", optional_value(k.detail_mpa), "EN 1993-1-9 detail category [MPa] (36 … 160)")(
        "delta-c-mpa", optional_value(k.delta_c_mpa), "a curve of your own: its range at 2e6 cycles [MPa], with --m1, --m2")(
        "m1", value(k.m1), "--delta-c-mpa: slope down to 5e6 cycles")(
        "m2", value(k.m2), "--delta-c-mpa: slope from 5e6 to 1e8 cycles (no damage below; 0: none below 5e6)")(
        "youngs-modulus-pa", value(k.youngs_modulus_pa), "strain channels: stress = E x strain [Pa] (default structural steel)")(
        "section-modulus-m3", optional_value(k.section_modulus_m3), "moment channels: stress = M / W at the detail [m3]")(
        "gamma-ff", value(k.gamma_ff), "partial factor on the ranges (EN 1993-1-9 gamma_Ff)")(
        "gamma-mf", value(k.gamma_mf), "partial factor on the strength (EN 1993-1-9 gamma_Mf, e.g. 1.35)")(
        "method", value(k.method), "three-point (ASTM E1049 5.4.4) or four-point")(
        "hysteresis-mpa", value(k.hysteresis_mpa), "reversals smaller than this are not turning points [MPa] (0: every one)")(
        "range-bin-mpa", value(k.range_bin_mpa), "cycles.csv: width of a range bin [MPa]")(
        "mean-bin-mpa", value(k.mean_bin_mpa), "cycles.csv: width of a mean bin [MPa]")(
        "mix", optional_value(k.mix), "a traffic mix file (data/trains/fatigue/mix-*.toml): the positional is a scenario, "
        "--channel a deck station's <station>_moment or <station>_strain");
  };
  c.usage_and_samples =
      "Counts the rainflow cycles of each channel (ASTM E1049 three-point with half cycles for the\n"
      "residue, or four-point), streamed, and sums their damage (Palmgren-Miner) against an\n"
      "S-N curve: EN 1993-1-9's of a detail category (slope 3 to 5e6 cycles, 5 to 1e8, none below)\n"
      "or one of your own. A channel in Pa or MPa is a stress; microstrain x E; N m / W. Ranges\n"
      "count as gamma_Ff x gamma_Mf x range. Writes OUT/cycles.csv (channel, range and mean bins\n"
      "in MPa without the factors, count: the range-mean matrix, long format), OUT/damage.csv (channel, curve,\n"
      "factors, cycles, cycles above the cut-off, largest range, damage D, the equivalent range at\n"
      "2e6 cycles, the record's duration, years to D = 1 if the record's traffic repeated) and\n"
      "manifest.toml. Method and limits: docs/fatigue.md.\n"
      "With --mix MIX the positional is a scenario: each train of the mix runs over its model at its\n"
      "speed (viaduct run's simulation), the --channel load effect's history is counted, and\n"
      "OUT/damage.csv holds per train the passages a day, the cycles, the damage of a passage and of\n"
      "a year (365 days), its share, and a last row 'total': D a year and years to D = 1. EN 1991-2\n"
      "Annex D's trains and mixes: data/trains/fatigue/ (to confirm against the standard).\n\n"
      "Sample runs:\n"
      "  viaduct fatigue data/records/passages/passage-01.csv --channel mid_strain --detail 71 --hysteresis-mpa 1 --out out/fatigue\n"
      "  viaduct fatigue scenarios/hslm-simply-supported.toml --mix data/trains/fatigue/mix-standard.toml --channel mid_moment --section-modulus-m3 0.05 --detail 71 --out out/fatigue-mix\n";
  const auto body = [](const Common& o, const FatigueOptions& k) {
    check_options(k);
    const study::FatigueCount f = count_of(k);
    return k.mix ? run_mix(o, k, f) : run_records(o, k, f);
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli

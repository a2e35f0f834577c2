// viaduct fatigue: rainflow cycles and Miner damage of a record's stress, strain or moment
// channels (issue #42, first part: measured and simulated histories; docs/fatigue.md).
#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "viaduct/io/results.hpp"
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
};

// [Pa] per unit of a channel, or an InputError naming what fatigue takes.
double to_pa(const io::Record& r, std::size_t ch, const FatigueOptions& k) {
  const std::string& u = r.units[ch];
  if (u == "Pa") return 1.0;
  if (u == "ue") return k.youngs_modulus_pa * 1e-6;
  if (u == "Nm") {
    if (!k.section_modulus_m3)
      throw InputError("channel " + r.channels[ch] + " is a moment [N m]: give --section-modulus-m3 W (sigma = M / W at the detail)");
    return 1.0 / *k.section_modulus_m3;
  }
  throw InputError("channel " + r.channels[ch] + " is in " + u +
                   ": fatigue needs a stress (Pa, MPa), a strain (microstrain, times --youngs-modulus-pa) or a moment "
                   "(N m, over --section-modulus-m3)");
}

study::SnCurve curve_of(const FatigueOptions& k) {
  if (k.detail_mpa.has_value() == k.delta_c_mpa.has_value())
    throw InputError("give exactly one of --detail (an EN 1993-1-9 category, MPa) or --delta-c-mpa (a curve of your own)");
  if (k.detail_mpa) return study::SnCurve::en1993_1_9(*k.detail_mpa);
  study::SnCurve c = study::SnCurve::two_slopes(*k.delta_c_mpa * 1e6, k.m1, k.m2);
  c.name = "user curve: " + format_number(*k.delta_c_mpa, 6) + " MPa at 2e6 cycles with slopes " + format_number(k.m1, 3) + " and " +
           format_number(k.m2, 3);
  return c;
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

std::string fatigue_cell(double v) { return io::table_cell(v, 8); }

// One channel: its cycles binned (range × mean, MPa) and its damage row.
void count_channel(const io::Record& in, std::size_t ch, const FatigueOptions& k, const study::SnCurve& curve,
                   std::vector<std::vector<std::string>>& cycle_rows, std::vector<std::vector<std::string>>& damage_rows, bool quiet) {
  const double pa = to_pa(in, ch, k);
  study::MinerSum miner(curve, pa, k.gamma_ff, k.gamma_mf);
  std::map<std::pair<long, long>, double> bins;  // (range bin, mean bin) → count, in MPa of the history
  const double mpa = pa * 1e-6;
  signal::Rainflow rf(
      [&](const signal::Cycle& c) {
        miner.add(c);
        bins[{static_cast<long>(std::floor(c.range * mpa / k.range_bin_mpa)), static_cast<long>(std::floor(c.mean * mpa / k.mean_bin_mpa))}] +=
            c.count;
      },
      signal::rainflow_method(k.method, "--method"), k.hysteresis_mpa / mpa);
  rf.push(Vector(in.data.col(static_cast<Index>(ch))));
  rf.finish();
  for (const auto& [b, n] : bins)
    cycle_rows.push_back({in.channels[ch], fatigue_cell(b.first * k.range_bin_mpa), fatigue_cell((b.first + 1) * k.range_bin_mpa), fatigue_cell(b.second * k.mean_bin_mpa),
                          fatigue_cell((b.second + 1) * k.mean_bin_mpa), fatigue_cell(n)});
  const double duration = static_cast<double>(in.n_samples() - 1) / in.fs_hz;
  const double years = miner.damage > 0.0 ? duration / miner.damage / (365.25 * 86400.0) : std::numeric_limits<double>::infinity();
  damage_rows.push_back({in.channels[ch], curve.name, fatigue_cell(k.gamma_ff), fatigue_cell(k.gamma_mf), fatigue_cell(miner.cycles), fatigue_cell(miner.damaging),
                         fatigue_cell(miner.max_range_pa * 1e-6), fatigue_cell(miner.damage), fatigue_cell(study::equivalent_range_2e6(miner.damage, curve) * 1e-6),
                         fatigue_cell(duration), std::isfinite(years) ? fatigue_cell(years) : ""});
  if (!quiet)
    std::printf("%-22s %.1f cycles (%.1f above the cut-off), largest range %.4g MPa; D = %.4g (%s years to D = 1 at this record's rate)\n",
                in.channels[ch].c_str(), miner.cycles, miner.damaging, miner.max_range_pa * 1e-6, miner.damage,
                std::isfinite(years) ? format_number(years, 4).c_str() : "no");
}

}  // namespace

Command fatigue_command() {
  Command c = record_command("fatigue", "RECORD", "rainflow cycles and Miner damage of stress, strain or moment channels (cycles.csv, damage.csv)");
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
        "mean-bin-mpa", value(k.mean_bin_mpa), "cycles.csv: width of a mean bin [MPa]");
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
      "manifest.toml. Method and limits: docs/fatigue.md.\n\n"
      "Sample runs:\n"
      "  viaduct fatigue data/records/passages/passage-01.csv --channel mid_strain --detail 71 --hysteresis-mpa 1 --out out/fatigue\n";
  const auto body = [](const Common& o, const FatigueOptions& k) {
    check_options(k);
    const study::SnCurve curve = curve_of(k);
    const io::Record whole = read_record(o.scenario, o);
    const auto chans = selected(whole, k.channels);
    for (std::size_t ch : chans) to_pa(whole, ch, k);  // every channel's unit checked before counting
    std::vector<std::vector<std::string>> cycle_rows, damage_rows;
    // Each channel over its own valid span: a gap in one channel cuts no other (usable() warns).
    for (std::size_t ch : chans) count_channel(usable(whole, {ch}, o), ch, k, curve, cycle_rows, damage_rows, o.quiet);
    make_out_dir(o.out);
    io::write_table_csv(o.out + "/cycles.csv", {"channel", "range_low_mpa", "range_high_mpa", "mean_low_mpa", "mean_high_mpa", "count"},
                        cycle_rows);
    write_table_outputs(o, "damage.csv",
                        {"channel", "curve", "gamma_ff", "gamma_mf", "cycles", "damaging_cycles", "max_range_mpa", "damage",
                         "equivalent_range_2e6_mpa", "duration_s", "years_to_d1_at_record_rate"},
                        damage_rows);
    if (!o.quiet) std::printf("wrote %s/cycles.csv, damage.csv\n", o.out.c_str());
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli

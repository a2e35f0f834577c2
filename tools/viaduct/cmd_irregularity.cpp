// viaduct irregularity: a random vertical rail profile from a spectrum, and its check.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "cli.hpp"
#include "viaduct/io/profile.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/load/irregularity.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::cli {

namespace {

struct IrregularityOptions {
  std::optional<std::string> spectrum, profile;
  double lambda_min = 1.0, lambda_max = 80.0, length = 500.0, dx = 0.05, x0 = 0.0;
  unsigned long long seed = 1;
  long nperseg = 4096;
};

constexpr double kTwoPi = 6.283185307179586;
constexpr load::IrregularitySpectrum kAllSpectra[] = {
    load::IrregularitySpectrum::fra1, load::IrregularitySpectrum::fra2, load::IrregularitySpectrum::fra3,
    load::IrregularitySpectrum::fra4, load::IrregularitySpectrum::fra5, load::IrregularitySpectrum::fra6,
    load::IrregularitySpectrum::german_low, load::IrregularitySpectrum::german_high};

// --profile: a measured profile's PSD in the band against every spectrum; the nearest named.
int analyse_profile(const Common& o, const IrregularityOptions& k) {
  if (k.spectrum) throw InputError("give --profile (analyse a measured profile) or --spectrum (make one), not both");
  const load::RailProfile p = io::read_rail_profile(*k.profile);
  const double length = p.dx * static_cast<double>(p.z.size() - 1);
  signal::WelchOptions w;
  w.nperseg = std::min<Index>(k.nperseg, p.z.size());
  const double seg = p.dx * static_cast<double>(w.nperseg);
  if (k.lambda_min < 4 * p.dx)
    throw InputError("--lambda-min = " + format_number(k.lambda_min) + ": violated constraint lambda_min >= 4 dx (the profile's step is " +
                     format_number(p.dx) + " m)");
  if (!(k.lambda_max > k.lambda_min) || k.lambda_max > seg)
    throw InputError("--lambda-max = " + format_number(k.lambda_max) + ": violated constraint lambda_min < lambda_max <= " + format_number(seg) +
                     " m (a Welch segment of --nperseg " + std::to_string(w.nperseg) + " samples; the profile is " + format_number(length) + " m)");
  const signal::Psd psd = signal::welch(p.z, 1.0 / p.dx, w);
  std::vector<std::string> names = {"wavenumber_rad_per_m", "wavelength_m", "psd_profile_m2_per_rad_per_m"};
  std::vector<std::vector<double>> cols(3 + std::size(kAllSpectra));
  std::vector<std::vector<double>> log_ratio(std::size(kAllSpectra));
  double var = 0;
  for (Index i = 1; i < psd.frequency_hz.size(); ++i) {
    const double omega = kTwoPi * psd.frequency_hz[i], lambda = 1.0 / psd.frequency_hz[i];
    if (lambda < k.lambda_min || lambda > k.lambda_max) continue;
    const double est = psd.density[i] / kTwoPi;
    var += psd.density[i] * (psd.frequency_hz[1] - psd.frequency_hz[0]);
    cols[0].push_back(omega), cols[1].push_back(lambda), cols[2].push_back(est);
    for (std::size_t s = 0; s < std::size(kAllSpectra); ++s) {
      const double target = load::irregularity_psd(kAllSpectra[s], omega);
      cols[3 + s].push_back(target);
      log_ratio[s].push_back(std::log(est / target));
    }
  }
  if (cols[0].size() < 3) throw InputError("fewer than 3 Welch bins in the band: widen --lambda-min/--lambda-max or raise --nperseg");
  if (!(var > 0)) throw InputError(*k.profile + ": the profile is flat in the band: no spectrum to compare");
  for (auto s : kAllSpectra) names.push_back(std::string("psd_") + load::spectrum_name(s) + "_m2_per_rad_per_m");
  for (auto& n : names) std::replace(n.begin(), n.end(), '-', '_');
  make_out_dir(o.out);
  std::vector<Vector> vcols;
  for (const auto& c : cols) vcols.push_back(Eigen::Map<const Vector>(c.data(), static_cast<Index>(c.size())));
  io::write_columns_csv(o.out + "/psd.csv", names, vcols);
  // The nearest spectrum: the smallest |median log ratio| over the band's bins.
  std::size_t best = 0;
  std::vector<double> median(std::size(kAllSpectra));
  for (std::size_t s = 0; s < median.size(); ++s) {
    auto v = log_ratio[s];
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    median[s] = std::exp(v[v.size() / 2]);
    if (std::abs(std::log(median[s])) < std::abs(std::log(median[best]))) best = s;
  }
  io::Manifest m = start_manifest(o, "irregularity", {*k.profile});
  m.extra = {{"rms_band_m", format_number(std::sqrt(var), 8)}, {"nearest_spectrum", "\"" + std::string(load::spectrum_name(kAllSpectra[best])) + "\""}};
  io::write_manifest(o.out + "/manifest.toml", m, nullptr);
  if (!o.quiet) {
    std::printf("%s: %ld points every %g m (%g m); RMS in %g-%g m: %.4g mm (Welch, %ld-point segments)\n", k.profile->c_str(),
                static_cast<long>(p.z.size()), p.dx, length, k.lambda_min, k.lambda_max, std::sqrt(var) * 1e3, static_cast<long>(w.nperseg));
    std::printf("measured PSD over each spectrum (median over %zu bins):", cols[0].size());
    for (std::size_t s = 0; s < median.size(); ++s) std::printf(" %s %.3g", load::spectrum_name(kAllSpectra[s]), median[s]);
    std::printf("\nnearest: %s\nwrote %s/psd.csv\n", load::spectrum_name(kAllSpectra[best]), o.out.c_str());
  }
  return ok;
}

int irregularity_body(const Common& o, const IrregularityOptions& k) {
  if (k.profile) return analyse_profile(o, k);
  if (!k.spectrum)
    throw InputError("--spectrum is required (fra1 ... fra6 (FRA classes, 6 the best track), german-low, german-high), or --profile FILE");
  load::ProfileSpec spec;
  spec.spectrum = load::irregularity_spectrum(*k.spectrum);
  spec.lambda_min = k.lambda_min;
  spec.lambda_max = k.lambda_max;
  spec.length = k.length;
  spec.dx = k.dx;
  spec.x0 = k.x0;
  spec.seed = k.seed;
  std::string why;
  if (!spec.is_valid(&why)) throw InputError(why);
  const load::RailProfile p = load::random_profile(spec);
  // The check: Welch's PSD of the profile (per cycle/m) as a density per rad/m, against the target.
  signal::WelchOptions w;
  w.nperseg = std::min<Index>(k.nperseg, p.z.size());
  const signal::Psd psd = signal::welch(p.z, 1.0 / spec.dx, w);
  constexpr double two_pi = kTwoPi;
  std::vector<double> wn, wl, target, est;
  std::vector<double> ratios;
  for (Index i = 1; i < psd.frequency_hz.size(); ++i) {
    const double omega = two_pi * psd.frequency_hz[i];
    const double lambda = 1.0 / psd.frequency_hz[i];
    if (lambda < spec.lambda_min || lambda > spec.lambda_max) continue;
    wn.push_back(omega);
    wl.push_back(lambda);
    target.push_back(load::irregularity_psd(spec.spectrum, omega));
    est.push_back(psd.density[i] / two_pi);
    ratios.push_back(est.back() / target.back());
  }
  const double rms = std::sqrt((p.z.array() - p.z.mean()).square().mean());
  const double sigma = std::sqrt(load::irregularity_variance(spec.spectrum, spec.lambda_min, spec.lambda_max));
  make_out_dir(o.out);
  Vector x(p.z.size());
  for (Index j = 0; j < x.size(); ++j) x[j] = p.x0 + p.dx * static_cast<double>(j);
  io::write_columns_csv(o.out + "/profile.csv", {"x_m", "z_m"}, {x, p.z});
  auto col = [](const std::vector<double>& v) { return Eigen::Map<const Vector>(v.data(), static_cast<Index>(v.size())); };
  io::write_columns_csv(o.out + "/psd.csv", {"wavenumber_rad_per_m", "wavelength_m", "psd_target_m2_per_rad_per_m", "psd_profile_m2_per_rad_per_m"},
                        {col(wn), col(wl), col(target), col(est)});
  io::Manifest m = start_manifest(o, "irregularity");
  m.extra = {{"spectrum", "\"" + std::string(load::spectrum_name(spec.spectrum)) + "\""},
             {"seed", std::to_string(spec.seed)},
             {"rms_m", format_number(rms, 8)},
             {"rms_closed_form_m", format_number(sigma, 8)}};
  io::write_manifest(o.out + "/manifest.toml", m, nullptr);
  if (!o.quiet) {
    std::sort(ratios.begin(), ratios.end());
    const double median = ratios.empty() ? NAN : ratios[ratios.size() / 2];
    std::printf("%s, wavelengths %g-%g m, %g m at %g m, seed %llu: RMS %.4g mm (the band's closed form %.4g mm)\n",
                load::spectrum_name(spec.spectrum), spec.lambda_min, spec.lambda_max, spec.length, spec.dx, k.seed, rms * 1e3, sigma * 1e3);
    std::printf("Welch PSD of the profile over the target in the band: median %.3f (%zu bins; a single record's estimate scatters)\n",
                median, ratios.size());
    std::printf("wrote %s/profile.csv and psd.csv\n", o.out.c_str());
  }
  return ok;
}

}  // namespace

Command irregularity_command() {
  Command c;
  c.name = "irregularity";
  c.needs_scenario = false;
  c.positional = "";
  c.summary = "rail irregularity: a random profile from a spectrum (profile.csv), or a measured profile's spectrum";
  const auto declare = [](po::options_description& d, IrregularityOptions& k) {
    d.add_options()("spectrum", optional_value(k.spectrum), "fra1 ... fra6 (US FRA classes, 6 the best track), german-low, german-high")(
        "profile", optional_value(k.profile), "a measured profile (CSV x_m,z_mm): its PSD against every spectrum, the nearest named")(
        "lambda-min", value(k.lambda_min), "shortest wavelength [m]")("lambda-max", value(k.lambda_max), "longest wavelength [m]")(
        "length", value(k.length), "profile length [m]")("dx", value(k.dx), "sampling step [m]")(
        "x0", value(k.x0), "start of the profile along the load path [m]")("seed", value(k.seed), "random seed (same seed, same profile)")(
        "nperseg", value(k.nperseg), "Welch segment length of the check [samples]");
  };
  c.usage_and_samples =
      "Harmonic superposition on the period of 2^k samples >= the length: every harmonic of the\n"
      "band with amplitude sqrt(2 x the integral of S over its cell) and a phase drawn from the seed (one per harmonic, in\n"
      "order: two bands from one seed share their common harmonics). Spectra (one-sided, per\n"
      "rad/m; docs/vehicles.md): FRA S = 0.25 Av Oc^2/(O^2 (O^2+Oc^2)), German S = Av Oc^2/((O^2+Or^2)\n"
      "(O^2+Oc^2)). Writes OUT/profile.csv (x_m,z_m), OUT/psd.csv (the band: target and Welch's\n"
      "estimate of the profile) and manifest.toml (RMS and the band's closed-form RMS).\n"
      "--profile FILE: a measured profile (x_m,z_mm; a uniform step) instead: its Welch PSD in the\n"
      "band against every spectrum (psd.csv), the median ratio to each and the nearest spectrum.\n"
      "The vehicle models of issue #21 will read such profiles; moving forces do not.\n\n"
      "Sample runs:\n"
      "  viaduct irregularity --spectrum fra6 --lambda-min 1 --lambda-max 80 --length 500 --seed 7 --out out/irregularity\n"
      "  viaduct irregularity --profile out/irregularity/profile.csv --lambda-min 1 --lambda-max 80 --out out/irregularity-check\n";
  bind(c, +declare, +irregularity_body);
  return c;
}

}  // namespace viaduct::cli

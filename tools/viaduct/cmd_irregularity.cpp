// viaduct irregularity: a random vertical rail profile from a spectrum, and its check.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/load/irregularity.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::cli {

namespace {

struct IrregularityOptions {
  std::optional<std::string> spectrum;
  double lambda_min = 1.0, lambda_max = 80.0, length = 500.0, dx = 0.05, x0 = 0.0;
  unsigned long long seed = 1;
  long nperseg = 4096;
};

int irregularity_body(const Common& o, const IrregularityOptions& k) {
  if (!k.spectrum) throw InputError("--spectrum is required: fra1 ... fra6 (FRA classes, 6 the best track), german-low, german-high");
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
  constexpr double two_pi = 6.283185307179586;
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
  c.summary = "a random vertical rail profile from an irregularity spectrum (profile.csv) and its PSD check";
  const auto declare = [](po::options_description& d, IrregularityOptions& k) {
    d.add_options()("spectrum", optional_value(k.spectrum), "fra1 ... fra6 (US FRA classes, 6 the best track), german-low, german-high")(
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
      "The vehicle models of issue #21 will read such profiles; moving forces do not.\n\n"
      "Sample runs:\n"
      "  viaduct irregularity --spectrum fra6 --lambda-min 1 --lambda-max 80 --length 500 --seed 7 --out out/irregularity\n";
  bind(c, +declare, +irregularity_body);
  return c;
}

}  // namespace viaduct::cli

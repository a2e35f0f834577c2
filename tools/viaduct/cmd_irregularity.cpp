// viaduct irregularity: a random vertical rail profile from a spectrum, and its check.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>

#include "cli.hpp"
#include "viaduct/io/profile.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/load/irregularity.hpp"
#include "viaduct/study/irregularity.hpp"

namespace viaduct::cli {

namespace {

struct IrregularityOptions {
  std::optional<std::string> spectrum, profile;
  double lambda_min = 1.0, lambda_max = 80.0, length = 500.0, dx = 0.05, x0 = 0.0;
  unsigned long long seed = 1;
  long nperseg = 4096;
};

// The psd.csv of a profile: its Welch PSD in the band, and beside it the target of `only` (a
// generated profile's spectrum) or of every spectrum.
void write_psd(const std::string& path, const study::ProfileSpectrum& ps, const load::IrregularitySpectrum* only) {
  std::vector<std::string> names = {"wavenumber_rad_per_m", "wavelength_m", "psd_profile_m2_per_rad_per_m"};
  std::vector<Vector> cols = {ps.wavenumber, (6.283185307179586 / ps.wavenumber.array()).matrix(), ps.psd};
  const std::vector<load::IrregularitySpectrum> targets = only ? std::vector<load::IrregularitySpectrum>{*only} : study::all_irregularity_spectra();
  for (const auto s : targets) {
    std::string n = only ? "psd_target_m2_per_rad_per_m" : std::string("psd_") + load::spectrum_name(s) + "_m2_per_rad_per_m";
    std::replace(n.begin(), n.end(), '-', '_');
    Vector t(ps.wavenumber.size());
    for (Index i = 0; i < t.size(); ++i) t[i] = load::irregularity_psd(s, ps.wavenumber[i]);
    // a generated profile's target stands before the profile's estimate, as the check reads
    names.insert(only ? names.begin() + 2 : names.end(), n);
    cols.insert(only ? cols.begin() + 2 : cols.end(), t);
  }
  io::write_columns_csv(path, names, cols);
}

// --profile: a measured profile's PSD in the band against every spectrum; the nearest named.
int analyse_profile(const Common& o, const IrregularityOptions& k) {
  if (k.spectrum) throw InputError("give --profile (analyse a measured profile) or --spectrum (make one), not both");
  const load::RailProfile p = io::read_rail_profile(*k.profile);
  study::ProfileSpectrum ps;
  try {
    ps = study::profile_spectrum(p, k.lambda_min, k.lambda_max, k.nperseg);
  } catch (const InputError& e) {
    throw InputError(*k.profile + ": " + e.what());
  }
  make_out_dir(o.out);
  write_psd(o.out + "/psd.csv", ps, nullptr);
  io::Manifest m = start_manifest(o, "irregularity", {*k.profile});
  m.extra = {{"rms_band_m", format_number(ps.rms_band, 8)}, {"nearest_spectrum", "\"" + std::string(load::spectrum_name(ps.nearest)) + "\""}};
  io::write_manifest(o.out + "/manifest.toml", m, nullptr);
  if (!o.quiet) {
    std::printf("%s: %ld points every %g m (%g m); RMS in %g-%g m: %.4g mm (Welch, %ld-point segments)\n", k.profile->c_str(),
                static_cast<long>(p.z.size()), p.dx, p.end() - p.x0, k.lambda_min, k.lambda_max, ps.rms_band * 1e3, static_cast<long>(ps.nperseg));
    std::printf("measured PSD over each spectrum (median over %ld bins):", static_cast<long>(ps.wavenumber.size()));
    for (std::size_t s = 0; s < ps.median_ratio.size(); ++s)
      std::printf(" %s %.3g", load::spectrum_name(study::all_irregularity_spectra()[s]), ps.median_ratio[s]);
    std::printf("\nnearest: %s\nwrote %s/psd.csv\n", load::spectrum_name(ps.nearest), o.out.c_str());
  }
  return ok;
}

int irregularity_body(const Common& o, const IrregularityOptions& k) {
  if (k.profile) return analyse_profile(o, k);
  if (!k.spectrum)
    throw InputError("--spectrum is required (fra1 ... fra6 (FRA classes, 6 the best track), german-low, german-high), or --profile FILE");
  const load::ProfileSpec spec{load::irregularity_spectrum(*k.spectrum), k.lambda_min, k.lambda_max, k.length, k.x0, k.dx, k.seed};
  std::string why;
  if (!spec.is_valid(&why)) throw InputError(why);
  const load::RailProfile p = load::random_profile(spec);
  // The check: the profile's Welch PSD against its spectrum.
  const study::ProfileSpectrum ps = study::profile_spectrum(p, spec.lambda_min, spec.lambda_max, k.nperseg);
  const double median = ps.median_ratio[static_cast<std::size_t>(spec.spectrum)];
  const double rms = std::sqrt((p.z.array() - p.z.mean()).square().mean());
  const double sigma = std::sqrt(load::irregularity_variance(spec.spectrum, spec.lambda_min, spec.lambda_max));
  make_out_dir(o.out);
  Vector x(p.z.size());
  for (Index j = 0; j < x.size(); ++j) x[j] = p.x0 + p.dx * static_cast<double>(j);
  io::write_columns_csv(o.out + "/profile.csv", {"x_m", "z_m"}, {x, p.z});
  write_psd(o.out + "/psd.csv", ps, &spec.spectrum);
  io::Manifest m = start_manifest(o, "irregularity");
  m.extra = {{"spectrum", "\"" + std::string(load::spectrum_name(spec.spectrum)) + "\""},
             {"seed", std::to_string(spec.seed)},
             {"rms_m", format_number(rms, 8)},
             {"rms_closed_form_m", format_number(sigma, 8)}};
  io::write_manifest(o.out + "/manifest.toml", m, nullptr);
  if (!o.quiet) {
    std::printf("%s, wavelengths %g-%g m, %g m at %g m, seed %llu: RMS %.4g mm (the band's closed form %.4g mm)\n",
                load::spectrum_name(spec.spectrum), spec.lambda_min, spec.lambda_max, spec.length, spec.dx, k.seed, rms * 1e3, sigma * 1e3);
    std::printf("Welch PSD of the profile over the target in the band: median %.3f (%ld bins; a single record's estimate scatters)\n",
                median, static_cast<long>(ps.wavenumber.size()));
    std::printf("wrote %s/profile.csv and psd.csv\n", o.out.c_str());
  }
  return ok;
}

}  // namespace

Command irregularity_command() {
  Command c = command("irregularity", "",
                      "rail irregularity: a random profile from a spectrum (profile.csv), or a measured profile's spectrum");
  c.needs_scenario = false;
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

#include "viaduct/study/irregularity.hpp"

#include <algorithm>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::study {

const std::vector<load::IrregularitySpectrum>& all_irregularity_spectra() {
  using S = load::IrregularitySpectrum;
  static const std::vector<S> all = {S::fra1, S::fra2, S::fra3, S::fra4, S::fra5, S::fra6, S::german_low, S::german_high};
  return all;
}

ProfileSpectrum profile_spectrum(const load::RailProfile& p, double lambda_min, double lambda_max, Index nperseg) {
  constexpr double two_pi = 6.283185307179586;
  if (p.z.size() < 4 || !(p.dx > 0)) throw InputError("profile spectrum: a profile of at least 4 samples and a step > 0");
  ProfileSpectrum r;
  r.nperseg = std::min<Index>(nperseg, p.z.size());
  const double seg = p.dx * static_cast<double>(r.nperseg);
  if (!(lambda_min >= 4 * p.dx))
    throw InputError("--lambda-min = " + format_number(lambda_min) + ": violated constraint lambda_min >= 4 dx (the profile's step is " +
                     format_number(p.dx) + " m)");
  if (!(lambda_max > lambda_min) || lambda_max > seg)
    throw InputError("--lambda-max = " + format_number(lambda_max) + ": violated constraint lambda_min < lambda_max <= " + format_number(seg) +
                     " m (a Welch segment of --nperseg " + std::to_string(r.nperseg) + " samples; the profile is " +
                     format_number(p.dx * static_cast<double>(p.z.size() - 1)) + " m)");
  signal::WelchOptions w;
  w.nperseg = r.nperseg;
  const signal::Psd psd = signal::welch(p.z, 1.0 / p.dx, w);
  std::vector<double> wn, est;
  double var = 0;
  for (Index i = 1; i < psd.frequency_hz.size(); ++i) {
    const double lambda = 1.0 / psd.frequency_hz[i];
    if (lambda < lambda_min || lambda > lambda_max) continue;
    wn.push_back(two_pi * psd.frequency_hz[i]);
    est.push_back(psd.density[i] / two_pi);  // per cycle/m -> per rad/m
    var += psd.density[i] * (psd.frequency_hz[1] - psd.frequency_hz[0]);
  }
  if (wn.size() < 3) throw InputError("fewer than 3 Welch bins in the band: widen --lambda-min/--lambda-max or raise --nperseg");
  if (!(var > 0)) throw InputError("the profile is flat in the band: no spectrum to compare");
  r.wavenumber = Eigen::Map<const Vector>(wn.data(), static_cast<Index>(wn.size()));
  r.psd = Eigen::Map<const Vector>(est.data(), static_cast<Index>(est.size()));
  r.rms_band = std::sqrt(var);
  double best = INFINITY;
  for (const auto s : all_irregularity_spectra()) {
    std::vector<double> lr;
    for (std::size_t i = 0; i < wn.size(); ++i) lr.push_back(std::log(est[i] / load::irregularity_psd(s, wn[i])));
    std::nth_element(lr.begin(), lr.begin() + static_cast<long>(lr.size() / 2), lr.end());
    r.median_ratio.push_back(std::exp(lr[lr.size() / 2]));
    if (std::abs(lr[lr.size() / 2]) < best) best = std::abs(lr[lr.size() / 2]), r.nearest = s;
  }
  return r;
}

}  // namespace viaduct::study

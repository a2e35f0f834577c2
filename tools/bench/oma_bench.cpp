// Benchmark (not a test) of output-only identification, issue #41's case: 30 minutes of 6
// channels at 100 Hz with 5 % sensor noise, five known modes (a pair 2 % apart), from the
// independent generator of tests/unit/ident/ambient.hpp.
//   viaduct_oma_bench [--minutes M] [--max-order N] [--repeats R] [--seed S]
// Prints the wall time of SSI-COV (stabilization over orders 2..N, clustering, jackknife) and
// FDD (median of R runs, one thread) and each true mode's estimate: f error, ζ error, MAC,
// standardised errors |Δf|/σ_f, |Δζ|/σ_ζ, and the spurious modes reported.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "../../tests/unit/ident/ambient.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/ident/oma.hpp"

using namespace viaduct;
using clk = std::chrono::steady_clock;

int main(int argc, char** argv) {
  double minutes = 30;
  int max_order = 60, repeats = 3;
  unsigned seed = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--minutes") minutes = std::atof(argv[i + 1]);
    else if (a == "--max-order") max_order = std::atoi(argv[i + 1]);
    else if (a == "--repeats") repeats = std::atoi(argv[i + 1]);
    else if (a == "--seed") seed = static_cast<unsigned>(std::atoi(argv[i + 1]));
    else {
      std::fprintf(stderr, "oma_bench: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const double fs = 100.0;
  const auto modes = vt::ambient_modes();
  const Matrix y = vt::ambient_record(modes, fs, static_cast<Index>(minutes * 60 * fs), 0.05, seed);
  std::printf("record %ld samples x %ld channels at %.0f Hz (%.1f min), 5 %% noise\n", static_cast<long>(y.rows()),
              static_cast<long>(y.cols()), fs, minutes);
  ident::SsiOptions o;
  o.f_min_hz = 1.0;
  o.f_max_hz = 20.0;
  o.max_order = max_order;
  std::vector<double> t_ssi, t_fdd;
  ident::SsiResult r;
  ident::FddResult fr;
  for (int k = 0; k < repeats; ++k) {
    auto t0 = clk::now();
    r = ident::ssi_cov(y, fs, o);
    t_ssi.push_back(std::chrono::duration<double>(clk::now() - t0).count());
    t0 = clk::now();
    ident::FddOptions fo;
    fo.f_min_hz = 1.0;
    fo.f_max_hz = 20.0;
    fr = ident::fdd(y, fs, fo);
    t_fdd.push_back(std::chrono::duration<double>(clk::now() - t0).count());
  }
  std::sort(t_ssi.begin(), t_ssi.end());
  std::sort(t_fdd.begin(), t_fdd.end());
  std::printf("ssi_cov_s %.3f (median of %d; block rows %ld, orders 2..%d)\nfdd_s %.3f\n", t_ssi[t_ssi.size() / 2], repeats,
              static_cast<long>(r.block_rows), max_order, t_fdd[t_fdd.size() / 2]);
  std::printf("%-8s %-9s %-9s %-8s %-8s %-6s %-6s\n", "f_true", "df_%", "dzeta_%", "MAC", "|df|/sf", "|dz|/sz", "EFDD_dz_%");
  std::vector<bool> used(r.modes.size(), false);
  for (const auto& m : modes) {
    ident::ComplexVector phi(static_cast<Index>(m.shape.size()));
    for (std::size_t c = 0; c < m.shape.size(); ++c) phi[static_cast<Index>(c)] = m.shape[c];
    std::size_t best = r.modes.size();
    double best_d = 1e9;
    for (std::size_t k = 0; k < r.modes.size(); ++k) {
      const double d = std::abs(r.modes[k].frequency_hz - m.f_hz);
      if (d < best_d) best_d = d, best = k;
    }
    if (best == r.modes.size() || best_d > 0.05 * m.f_hz) {
      std::printf("%-8.3f not found\n", m.f_hz);
      continue;
    }
    used[best] = true;
    const ident::OmaMode& e = r.modes[best];
    const double mac = ident::mac(e.shape, phi)(0, 0);
    double efdd = NAN;
    for (const auto& fm : fr.modes)
      if (std::abs(fm.frequency_hz - m.f_hz) < 0.01 * m.f_hz) efdd = 100 * (fm.efdd_damping_ratio - m.zeta) / m.zeta;
    std::printf("%-8.3f %-9.4f %-9.2f %-8.4f %-8.2f %-6.2f %-6.1f\n", m.f_hz, 100 * (e.frequency_hz - m.f_hz) / m.f_hz,
                100 * (e.damping_ratio - m.zeta) / m.zeta, mac, std::abs(e.frequency_hz - m.f_hz) / e.frequency_std_hz,
                std::abs(e.damping_ratio - m.zeta) / e.damping_std, efdd);
  }
  for (std::size_t k = 0; k < r.modes.size(); ++k)
    if (!used[k])
      std::printf("spurious %.4f Hz zeta %.4f (%ld poles) %s\n", r.modes[k].frequency_hz, r.modes[k].damping_ratio,
                  static_cast<long>(r.modes[k].n_poles), r.modes[k].note.c_str());
  return 0;
}

// Recovery errors of the identification methods on synthetic cases with known modal properties
// (issue #4): prints markdown tables. Run by scripts/measure/ident_accuracy.sh (docs/identification.md).
//   viaduct_ident_recovery [SOURCE_DIR]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "viaduct/core/eigensolvers.hpp"

#include "../../tests/unit/ident/synthetic.hpp"
#include "viaduct/ident/decay.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/study/forced.hpp"

using namespace viaduct;
using namespace viaduct::ident;

namespace {

constexpr int kSeeds = 20;  // noise realisations per case

struct Errors {
  std::vector<double> f, z;
  void add(double f_est, double f_true, double z_est, double z_true) {
    f.push_back(std::abs(f_est / f_true - 1));
    z.push_back(std::isfinite(z_est) ? std::abs(z_est / z_true - 1) : INFINITY);
  }
  static double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? NAN : v[v.size() / 2];
  }
  static double worst(const std::vector<double>& v) { return v.empty() ? NAN : *std::max_element(v.begin(), v.end()); }
  void row(const std::string& what) const {
    std::printf("| %s | %.4f | %.4f | %.2f | %.2f |\n", what.c_str(), 100 * median(f), 100 * worst(f), 100 * median(z), 100 * worst(z));
  }
};

void header(const char* title) {
  std::printf("\n%s\n\n| case | f error median [%%] | f error worst [%%] | ζ error median [%%] | ζ error worst [%%] |\n|---|---|---|---|---|\n", title);
}

}  // namespace

namespace {

void one_mode_table() {
  header("**One mode from an accelerance FRF** (5 Hz, 2001 lines over 2.5–7.5 Hz, complex noise at 1 % of the FRF's rms):");
  for (double zeta : {0.005, 0.01, 0.02, 0.05}) {
    vt::ModalSystem m;
    m.f_hz = {5.0};
    m.zeta = {zeta};
    m.shapes = {{1.0}};
    Errors pp, cf, ls;
    for (int s = 0; s < kSeeds; ++s) {
      const Frf frf = m.frf(vt::grid(2.5, 7.5, 2001), FrfQuantity::accelerance, 40.0, 100 + s);
      PeakPickingOptions po;
      po.max_modes = 1;
      const auto p = peak_picking(frf, po);
      pp.add(p[0].frequency_hz, 5.0, p[0].damping_ratio, zeta);
      const auto c = circle_fit(frf, 0, p[0].frequency_hz, std::isfinite(p[0].damping_ratio) ? p[0].damping_ratio : 0.02);
      cf.add(c.frequency_hz, 5.0, c.damping_ratio, zeta);
      LscfOptions lo;
      lo.max_order = 24;
      const auto r = lscf(frf, lo);
      if (r.modes.size() == 1) ls.add(r.modes[0].frequency_hz, 5.0, r.modes[0].damping_ratio, zeta);
      else ls.add(NAN, 5.0, NAN, zeta);
    }
    char b[64];
    std::snprintf(b, sizeof b, "ζ = %.1f %%", 100 * zeta);
    pp.row(std::string(b) + ", peak picking (half power)");
    cf.row(std::string(b) + ", circle fit");
    ls.row(std::string(b) + ", LSCF");
  }

}

void two_modes_table() {
  header("**Two modes 2 % apart** (6.00 and 6.12 Hz, three sensors, LSCF order ≤ 32, shapes by LSFD):");
  for (double zeta : {0.005, 0.01, 0.02, 0.05}) {
    vt::ModalSystem m;
    m.f_hz = {6.0, 6.12};
    m.zeta = {zeta, zeta};
    m.shapes = {{1.0, 0.8, 0.4}, {0.5, -0.6, 1.0}};
    Errors e;
    double worst_mac = 1.0;
    int missed = 0;
    for (int s = 0; s < kSeeds; ++s) {
      const Frf frf = m.frf(vt::grid(4.5, 7.5, 3001), FrfQuantity::accelerance, 40.0, 200 + s);
      LscfOptions lo;
      lo.max_order = 32;
      const auto r = lscf(frf, lo);
      if (r.modes.size() != 2) {
        ++missed;
        continue;
      }
      for (int k = 0; k < 2; ++k) {
        e.add(r.modes[k].frequency_hz, m.f_hz[k], r.modes[k].damping_ratio, m.zeta[k]);
        ComplexMatrix a(3, 1), b(3, 1);
        for (int o = 0; o < 3; ++o) b(o, 0) = m.shapes[k][o];
        a.col(0) = r.modes[k].shape;
        worst_mac = std::min(worst_mac, mac(a, b)(0, 0));
      }
    }
    char b[96];
    std::snprintf(b, sizeof b, "ζ = %.1f %%, LSCF (worst MAC %.4f, %d of %d runs without two modes)", 100 * zeta, worst_mac, missed, kSeeds);
    e.row(b);
  }

}

void decay_table() {
  header("**Free decay** (3 Hz mode after a forced part, 200 Hz sampling, noise at 1 % of the initial amplitude, start detected):");
  for (double zeta : {0.005, 0.01, 0.02, 0.05}) {
    Errors ld, ef, hb;
    double worst_start = 0;
    for (int s = 0; s < kSeeds; ++s) {
      const double fs = 200.0, f = 3.0, t_free = 10.0;
      const double T = t_free + 1.5 * std::log(100.0) / (2 * M_PI * f * zeta);
      const Index n = static_cast<Index>(T * fs);
      Vector x(n);
      const double wn = 2 * M_PI * f, wd = wn * std::sqrt(1 - zeta * zeta);
      for (Index k = 0; k < n; ++k) {
        const double t = k / fs;
        x[k] = t < t_free ? (t / t_free) * std::sin(0.93 * wn * (t - t_free)) : std::exp(-zeta * wn * (t - t_free)) * std::sin(wd * (t - t_free));
      }
      std::mt19937 rng(300 + s);
      std::normal_distribution<double> g(0.0, 0.01 / std::sqrt(2.0));
      for (Index k = 0; k < n; ++k) x[k] += g(rng);
      DecayOptions o;
      o.frequency_hz = 3.1;
      const DecayResult r = analyse_decay(x, fs, 0.0, o);
      ld.add(r.frequency_hz, f, r.zeta_log_decrement, zeta);
      ef.add(r.frequency_hz, f, r.zeta_envelope_fit, zeta);
      hb.add(r.frequency_hilbert_hz, f, r.zeta_hilbert, zeta);
      worst_start = std::max(worst_start, std::abs(r.start_s - t_free) * f);
    }
    char b[64];
    std::snprintf(b, sizeof b, "ζ = %.1f %%", 100 * zeta);
    ld.row(std::string(b) + ", logarithmic decrement");
    ef.row(std::string(b) + ", envelope fit");
    char c[128];
    std::snprintf(c, sizeof c, "%s, Hilbert (start found within %.2f cycles)", b, worst_start);
    hb.row(c);
  }

}

// The Old Guadiana model: a simulated stepped-sine test with noise, against the model's own
// complex modes (frequency and damping of the damped model, track dashpots included).
void old_guadiana_table(const std::string& src) {
  const io::FlatScenario flat = io::load_flat(src + "/scenarios/old-guadiana-talgo.toml");
  const study::Scenario sc = io::to_scenario(flat);
  const model::Structure s = model::build_structure(sc.bridge, sc.track);
  const Index n = s.n_dofs;
  const Matrix M(s.M), K(s.K), C(s.C);
  Matrix A = Matrix::Zero(2 * n, 2 * n);
  const Eigen::LLT<Matrix> llt(M);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -llt.solve(K);
  A.bottomRightCorner(n, n) = -llt.solve(C);
  const Eigen::EigenSolver<Matrix> es(A, false);
  std::vector<std::pair<double, double>> model_modes;  // (f, ζ) of the damped model near 10 Hz
  for (Index i = 0; i < es.eigenvalues().size(); ++i) {
    const auto l = es.eigenvalues()[i];
    const double f = std::abs(l) / (2 * M_PI);
    if (l.imag() > 0 && f > 9.0 && f < 11.0) model_modes.push_back({f, -l.real() / std::abs(l)});
  }
  std::sort(model_modes.begin(), model_modes.end());
  study::ForcedSetup setup;
  setup.force_x_m = 6.0;
  setup.responses = sc.stations;
  study::ShakerTest t;
  t.steps = regular_schedule(8.0, 12.0, 81, 8.0);
  t.fs_hz = 100.0;
  const auto rec = study::simulate_shaker_test(s, setup, t);
  std::printf("\n**Old Guadiana, simulated stepped-sine test** (exciter at x = 6 m, 81 steps 8–12 Hz of 8 s each, "
              "100 Hz, %ld Newmark steps): LSCF (order ≤ 20) against the damped model's complex modes "
              "(%.4f Hz / %.3f %% and %.4f Hz / %.3f %%: 0.5 %% apart):\n\n"
              "| noise | modes found | f error [%%] | ζ error [%%] |\n|---|---|---|---|\n",
              static_cast<long>(rec.n_steps), model_modes.at(0).first, 100 * model_modes.at(0).second,
              model_modes.at(1).first, 100 * model_modes.at(1).second);
  for (double snr : {-1.0, 60.0, 40.0}) {
    Vector force = rec.force;
    Matrix resp = rec.responses;
    std::mt19937 rng(17);
    if (snr > 0) {
      vt::add_noise(force, snr, rng);
      for (Index c = 0; c < resp.cols(); ++c) {
        Vector col = resp.col(c);
        vt::add_noise(col, snr, rng);
        resp.col(c) = col;
      }
    }
    const auto pts = stepped_sine(force, resp, rec.fs_hz, 0.0, t.steps, SteppedSineOptions{});
    Frf frf;
    frf.frequency_hz.resize(static_cast<Index>(pts.size()));
    frf.h.resize(static_cast<Index>(pts.size()), resp.cols());
    for (std::size_t k = 0; k < pts.size(); ++k) {
      frf.frequency_hz[static_cast<Index>(k)] = pts[k].frequency_hz;
      frf.h.row(static_cast<Index>(k)) = pts[k].h.transpose();
    }
    frf.responses = rec.names;
    frf.quantity.assign(rec.names.size(), FrfQuantity::accelerance);
    LscfOptions lo;
    lo.max_order = 20;
    const auto r = lscf(frf, lo);
    std::string fe, ze;
    for (std::size_t k = 0; k < r.modes.size(); ++k) {
      // Compare with the nearest model mode.
      std::size_t j = 0;
      for (std::size_t q = 1; q < model_modes.size(); ++q)
        if (std::abs(model_modes[q].first - r.modes[k].frequency_hz) < std::abs(model_modes[j].first - r.modes[k].frequency_hz)) j = q;
      char b[64];
      std::snprintf(b, sizeof b, "%s%.3f", k ? ", " : "", 100 * std::abs(r.modes[k].frequency_hz / model_modes[j].first - 1));
      fe += b;
      std::snprintf(b, sizeof b, "%s%.2f", k ? ", " : "", 100 * std::abs(r.modes[k].damping_ratio / model_modes[j].second - 1));
      ze += b;
    }
    std::printf("| %s | %zu | %s | %s |\n", snr < 0 ? "none" : (std::to_string(static_cast<int>(snr)) + " dB").c_str(), r.modes.size(),
                fe.c_str(), ze.c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  const std::string src = argc > 1 ? argv[1] : ".";
  const auto t0 = std::chrono::steady_clock::now();
  std::printf("Errors relative to the true value, over %d noise realisations per case (40 dB SNR).\n", kSeeds);
  one_mode_table();
  two_modes_table();
  decay_table();
  old_guadiana_table(src);
  std::printf("\nMeasured in %.1f s.\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

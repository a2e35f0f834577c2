#pragma once
// Synthetic modal systems with known frequencies, damping and shapes (unit modal masses), for the
// identification tests: exact FRFs, noise at a given signal-to-noise ratio, time responses.
#include <cmath>
#include <complex>
#include <functional>
#include <random>
#include <vector>

#include "viaduct/ident/frf.hpp"
#include "viaduct/solve/second_order_system.hpp"

namespace vt {

using viaduct::Index;
using viaduct::Matrix;
using viaduct::Vector;
using Complex = std::complex<double>;

struct ModalSystem {
  std::vector<double> f_hz;        // natural frequencies
  std::vector<double> zeta;        // damping ratios
  std::vector<std::vector<double>> shapes;  // shapes[r][o]: mode r at response o (unit modal mass)
  Index input = 0;                 // response index where the force acts

  Index n_out() const { return static_cast<Index>(shapes.front().size()); }
  // Receptance H_o(f) = Σ φ_or φ_in / (ω_r² − ω² + 2iζ_r ω_r ω).
  Complex receptance(Index o, double f) const {
    const double w = 2 * M_PI * f;
    Complex h = 0;
    for (std::size_t r = 0; r < f_hz.size(); ++r) {
      const double wr = 2 * M_PI * f_hz[r];
      h += shapes[r][static_cast<std::size_t>(o)] * shapes[r][static_cast<std::size_t>(input)] /
           Complex(wr * wr - w * w, 2 * zeta[r] * wr * w);
    }
    return h;
  }
  // FRF of every output on `f` (receptance or accelerance), with complex Gaussian noise whose rms
  // is the FRF's rms over f divided by 10^(snr_db/20) (snr_db < 0: no noise).
  viaduct::ident::Frf frf(const Vector& f, viaduct::ident::FrfQuantity q, double snr_db, unsigned seed = 7) const {
    viaduct::ident::Frf r;
    r.frequency_hz = f;
    r.h.resize(f.size(), n_out());
    for (Index o = 0; o < n_out(); ++o) {
      r.responses.push_back("s" + std::to_string(o));
      r.quantity.push_back(q);
      for (Index k = 0; k < f.size(); ++k) {
        const Complex iw(0, 2 * M_PI * f[k]);
        const Complex d = receptance(o, f[k]);
        r.h(k, o) = q == viaduct::ident::FrfQuantity::accelerance ? iw * iw * d
                    : q == viaduct::ident::FrfQuantity::mobility  ? iw * d
                                                                  : d;
      }
    }
    if (snr_db >= 0) {
      std::mt19937 rng(seed);
      std::normal_distribution<double> g(0.0, 1.0);
      for (Index o = 0; o < n_out(); ++o) {
        const double rms = std::sqrt(r.h.col(o).squaredNorm() / static_cast<double>(f.size()));
        const double s = rms * std::pow(10.0, -snr_db / 20.0) / std::sqrt(2.0);
        for (Index k = 0; k < f.size(); ++k) r.h(k, o) += Complex(s * g(rng), s * g(rng));
      }
    }
    return r;
  }
};

// The same system as M a + C v + K u = f in physical coordinates (Φ square and invertible):
// M = Φ^-T Φ^-1, K = Φ^-T Ω² Φ^-1, C = Φ^-T 2ζΩ Φ^-1; force history given as a function.
class PhysicalSystem : public viaduct::solve::SecondOrderSystem {
 public:
  template <class F>
  PhysicalSystem(const ModalSystem& m, F force) : force_(force), input_(m.input) {
    const Index n = static_cast<Index>(m.f_hz.size());
    Matrix Phi(n, n);
    for (Index r = 0; r < n; ++r)
      for (Index o = 0; o < n; ++o) Phi(o, r) = m.shapes[static_cast<std::size_t>(r)][static_cast<std::size_t>(o)];
    const Matrix Pi = Phi.inverse();
    Vector w2(n), c(n);
    for (Index r = 0; r < n; ++r) {
      const double wr = 2 * M_PI * m.f_hz[static_cast<std::size_t>(r)];
      w2[r] = wr * wr;
      c[r] = 2 * m.zeta[static_cast<std::size_t>(r)] * wr;
    }
    M_ = (Pi.transpose() * Pi).sparseView();
    K_ = (Pi.transpose() * w2.asDiagonal() * Pi).sparseView();
    C_ = (Pi.transpose() * c.asDiagonal() * Pi).sparseView();
  }
  const viaduct::SparseMatrix& mass() const override { return M_; }
  const viaduct::SparseMatrix& damping() const override { return C_; }
  const viaduct::SparseMatrix& stiffness() const override { return K_; }
  void force(double t, Vector& f) const override {
    f.setZero();
    f[input_] = force_(t);
  }

 private:
  std::function<double(double)> force_;
  Index input_;
  viaduct::SparseMatrix M_, C_, K_;
};

// Adds Gaussian noise with rms = rms(x) / 10^(snr_db/20).
inline void add_noise(Vector& x, double snr_db, std::mt19937& rng) {
  const double rms = std::sqrt(x.squaredNorm() / static_cast<double>(x.size()));
  std::normal_distribution<double> g(0.0, rms * std::pow(10.0, -snr_db / 20.0));
  for (Index k = 0; k < x.size(); ++k) x[k] += g(rng);
}

inline Vector grid(double a, double b, Index n) { return Vector::LinSpaced(n, a, b); }

}  // namespace vt

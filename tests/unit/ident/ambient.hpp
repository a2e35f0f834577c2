#pragma once
// Ambient-vibration records of known modes for the output-only identification tests and
// benchmark, from a generator independent of viaduct's solvers: each mode an exact discrete
// state-space SDOF (zero-order-hold white-noise force, the matrix exponential in closed form),
// outputs the sum of modal displacements times the shapes, plus white sensor noise.
#include <cmath>
#include <random>
#include <vector>

#include "viaduct/core/types.hpp"

namespace vt {

struct AmbientMode {
  double f_hz;
  double zeta;
  std::vector<double> shape;  // per channel
};

// Five modes over six channels: bending-like shapes and a torsion-like one 2 % above the second,
// with ζ from 0.8 % to 2 %.
inline std::vector<AmbientMode> ambient_modes() {
  const double pi = 3.14159265358979323846;
  std::vector<AmbientMode> m = {{2.0, 0.010, {}}, {4.0, 0.015, {}}, {4.08, 0.010, {}}, {7.5, 0.020, {}}, {11.0, 0.008, {}}};
  for (int c = 0; c < 6; ++c) {
    const double x = (c % 3 + 1) / 4.0;           // three sections along a span, two lines of sensors
    const double side = c < 3 ? 1.0 : -1.0;
    m[0].shape.push_back(std::sin(pi * x));
    m[1].shape.push_back(std::sin(2 * pi * x) * (c < 3 ? 1.0 : 0.9));
    m[2].shape.push_back(side * std::sin(pi * x));  // torsion of the first bending
    m[3].shape.push_back(std::sin(3 * pi * x) + 0.3 * side);
    m[4].shape.push_back(side * std::sin(2 * pi * x) + 0.2);
  }
  return m;
}

// n samples at fs of the modes, each mode forced to about the same rms; sensor noise of
// `noise` times each channel's rms. Columns: channels.
inline viaduct::Matrix ambient_record(const std::vector<AmbientMode>& modes, double fs, viaduct::Index n, double noise, unsigned seed,
                                      double frequency_scale = 1.0) {
  const std::size_t nc = modes.front().shape.size();
  viaduct::Matrix y = viaduct::Matrix::Zero(n, static_cast<viaduct::Index>(nc));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double dt = 1.0 / fs;
  const double w1 = 2 * 3.14159265358979323846 * modes.front().f_hz * frequency_scale;
  for (const AmbientMode& m : modes) {
    const double w = 2 * 3.14159265358979323846 * m.f_hz * frequency_scale, s = m.zeta * w, wd = w * std::sqrt(1 - m.zeta * m.zeta);
    const double e = std::exp(-s * dt), c = std::cos(wd * dt), sn = std::sin(wd * dt);
    const double p00 = e * (c + s / wd * sn), p01 = e * sn / wd, p10 = -e * w * w / wd * sn, p11 = e * (c - s / wd * sn);
    const double g0 = (-2 * s * p01 - (p11 - 1)) / (w * w), g1 = p01;  // A⁻¹(Φ − I)B
    const double gain = std::pow(w / w1, 1.5) * std::sqrt(m.zeta / modes.front().zeta);
    double q = 0, v = 0;
    for (viaduct::Index k = 0; k < n + 2000; ++k) {  // 2000 samples of run-in, then recorded
      const double u = gain * gauss(rng);
      const double qn = p00 * q + p01 * v + g0 * u, vn = p10 * q + p11 * v + g1 * u;
      q = qn;
      v = vn;
      if (k >= 2000)
        for (std::size_t ch = 0; ch < nc; ++ch) y(k - 2000, static_cast<viaduct::Index>(ch)) += m.shape[ch] * q;
    }
  }
  for (viaduct::Index ch = 0; ch < y.cols(); ++ch) {
    const double rms = std::sqrt(y.col(ch).squaredNorm() / static_cast<double>(n));
    for (viaduct::Index k = 0; k < n; ++k) y(k, ch) += noise * rms * gauss(rng);
  }
  return y;
}

// The free decay of the same modes from random initial displacements, sampled at fs.
inline viaduct::Matrix free_decay_record(const std::vector<AmbientMode>& modes, double fs, viaduct::Index n, double noise, unsigned seed) {
  const std::size_t nc = modes.front().shape.size();
  viaduct::Matrix y = viaduct::Matrix::Zero(n, static_cast<viaduct::Index>(nc));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (const AmbientMode& m : modes) {
    const double w = 2 * 3.14159265358979323846 * m.f_hz, s = m.zeta * w, wd = w * std::sqrt(1 - m.zeta * m.zeta);
    const double a = 1.0 + 0.3 * gauss(rng), phase = gauss(rng);
    for (viaduct::Index k = 0; k < n; ++k) {
      const double t = static_cast<double>(k) / fs;
      const double q = a * std::exp(-s * t) * std::cos(wd * t + phase);
      for (std::size_t ch = 0; ch < nc; ++ch) y(k, static_cast<viaduct::Index>(ch)) += m.shape[ch] * q;
    }
  }
  const double rms = std::sqrt(y.squaredNorm() / static_cast<double>(y.size()));
  for (viaduct::Index k = 0; k < y.size(); ++k) y.data()[k] += noise * rms * gauss(rng);
  return y;
}

}  // namespace vt

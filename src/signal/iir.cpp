#include "viaduct/signal/iir.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/core/simd.hpp"

namespace viaduct::signal {

namespace {

using cd = std::complex<double>;

std::string num(double v) { return format_number(v, 10); }

struct Zpk {
  std::vector<cd> z, p;
  double k = 1.0;
};

// Analog Chebyshev I prototype (SciPy cheb1ap).
Zpk cheb1ap(int N, double rp) {
  Zpk out;
  const double eps = std::sqrt(std::pow(10.0, 0.1 * rp) - 1.0);
  const double mu = 1.0 / N * std::asinh(1.0 / eps);
  cd prod = 1.0;
  for (int m = -N + 1; m < N; m += 2) {
    const double theta = M_PI * m / (2.0 * N);
    const cd p = -std::sinh(cd(mu, theta));
    out.p.push_back(p);
    prod *= -p;
  }
  out.k = prod.real();
  if (N % 2 == 0) out.k /= std::sqrt(1.0 + eps * eps);
  return out;
}

Zpk lp2lp(const Zpk& in, double wo) {
  Zpk o;
  const int degree = static_cast<int>(in.p.size() - in.z.size());
  for (auto z : in.z) o.z.push_back(z * wo);
  for (auto p : in.p) o.p.push_back(p * wo);
  o.k = in.k * std::pow(wo, degree);
  return o;
}

Zpk lp2hp(const Zpk& in, double wo) {
  Zpk o;
  const int degree = static_cast<int>(in.p.size() - in.z.size());
  cd pz = 1.0, pp = 1.0;
  for (auto z : in.z) {
    o.z.push_back(wo / z);
    pz *= -z;
  }
  for (auto p : in.p) {
    o.p.push_back(wo / p);
    pp *= -p;
  }
  for (int i = 0; i < degree; ++i) o.z.push_back(0.0);
  o.k = in.k * (pz / pp).real();
  return o;
}

Zpk lp2bp(const Zpk& in, double wo, double bw) {
  Zpk o;
  const int degree = static_cast<int>(in.p.size() - in.z.size());
  std::vector<cd> zl, pl;
  for (auto z : in.z) zl.push_back(z * bw / 2.0);
  for (auto p : in.p) pl.push_back(p * bw / 2.0);
  for (auto z : zl) o.z.push_back(z + std::sqrt(z * z - wo * wo));
  for (auto z : zl) o.z.push_back(z - std::sqrt(z * z - wo * wo));
  for (auto p : pl) o.p.push_back(p + std::sqrt(p * p - wo * wo));
  for (auto p : pl) o.p.push_back(p - std::sqrt(p * p - wo * wo));
  for (int i = 0; i < degree; ++i) o.z.push_back(0.0);
  o.k = in.k * std::pow(bw, degree);
  return o;
}

Zpk bilinear(const Zpk& in, double fs) {
  Zpk o;
  const double fs2 = 2.0 * fs;
  const int degree = static_cast<int>(in.p.size() - in.z.size());
  cd nz = 1.0, np = 1.0;
  for (auto z : in.z) {
    o.z.push_back((fs2 + z) / (fs2 - z));
    nz *= (fs2 - z);
  }
  for (auto p : in.p) {
    o.p.push_back((fs2 + p) / (fs2 - p));
    np *= (fs2 - p);
  }
  for (int i = 0; i < degree; ++i) o.z.push_back(-1.0);
  o.k = in.k * (nz / np).real();
  return o;
}

// One representative per complex-conjugate pair (positive imaginary part) plus reals, with
// conjugates averaged as SciPy's _cplxreal does.
std::vector<cd> cplxreal(const std::vector<cd>& v) {
  const double tol = 100 * std::numeric_limits<double>::epsilon();
  std::vector<cd> reals, pos, neg;
  for (auto x : v) {
    if (std::abs(x.imag()) <= tol * std::abs(x)) reals.emplace_back(x.real(), 0.0);
    else if (x.imag() > 0) pos.push_back(x);
    else neg.push_back(x);
  }
  if (pos.size() != neg.size()) throw SolverError("filter design: unpaired complex root");
  auto by_real = [](cd a, cd b) { return a.real() < b.real() || (a.real() == b.real() && std::abs(a.imag()) < std::abs(b.imag())); };
  std::sort(pos.begin(), pos.end(), by_real);
  std::sort(neg.begin(), neg.end(), by_real);
  std::vector<cd> out;
  for (std::size_t i = 0; i < pos.size(); ++i) out.push_back((pos[i] + std::conj(neg[i])) / 2.0);
  std::sort(reals.begin(), reals.end(), by_real);
  out.insert(out.end(), reals.begin(), reals.end());
  return out;
}

bool is_real(cd x) { return x.imag() == 0.0; }

enum class Which { real, complex, any };
std::size_t nearest(const std::vector<cd>& from, cd to, Which which) {
  std::size_t best = from.size();
  double bd = 0.0;
  for (std::size_t i = 0; i < from.size(); ++i) {
    if (which == Which::real && !is_real(from[i])) continue;
    if (which == Which::complex && is_real(from[i])) continue;
    const double d = std::abs(from[i] - to);
    if (best == from.size() || d < bd) {
      best = i;
      bd = d;
    }
  }
  if (best == from.size()) throw SolverError("filter design: no zero to pair with a pole");
  return best;
}

std::size_t idx_worst(const std::vector<cd>& p, const std::vector<std::size_t>& among) {
  std::size_t best = among.front();
  for (auto i : among)
    if (std::abs(1.0 - std::abs(p[i])) < std::abs(1.0 - std::abs(p[best]))) best = i;
  return best;
}

Section single(const std::vector<cd>& z, const std::vector<cd>& p) {
  // poly of up to two roots, right-aligned as in SciPy's _single_zpksos.
  auto poly = [](const std::vector<cd>& r, double* out) {
    if (r.size() == 2) {
      out[0] = 1.0;
      out[1] = (-(r[0] + r[1])).real();
      out[2] = (r[0] * r[1]).real();
    } else if (r.size() == 1) {
      out[0] = 0.0;
      out[1] = 1.0;
      out[2] = (-r[0]).real();
    } else {
      out[0] = 0.0;
      out[1] = 0.0;
      out[2] = 1.0;
    }
  };
  Section s{};
  poly(z, &s[0]);
  poly(p, &s[3]);
  return s;
}

template <class T>
T take(std::vector<T>& v, std::size_t i) {
  T x = v[i];
  v.erase(v.begin() + static_cast<std::ptrdiff_t>(i));
  return x;
}

// SciPy zpk2sos with pairing='nearest' (digital).
Sos zpk2sos(Zpk zpk) {
  std::vector<cd> z = zpk.z, p = zpk.p;
  while (p.size() < z.size()) p.push_back(0.0);
  while (z.size() < p.size()) z.push_back(0.0);
  const std::size_t n_sections = (p.size() + 1) / 2;
  if (p.size() % 2 == 1) {
    p.push_back(0.0);
    z.push_back(0.0);
  }
  z = cplxreal(z);
  p = cplxreal(p);
  Sos sos;
  sos.sections.assign(n_sections, Section{});
  for (std::size_t si = n_sections; si-- > 0;) {
    std::vector<std::size_t> all(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) all[i] = i;
    const cd p1 = take(p, idx_worst(p, all));
    const std::size_t n_real_p = static_cast<std::size_t>(std::count_if(p.begin(), p.end(), is_real));
    const std::size_t n_real_z = static_cast<std::size_t>(std::count_if(z.begin(), z.end(), is_real));
    if (is_real(p1) && n_real_p == 0) {
      const cd z1 = take(z, nearest(z, p1, Which::real));
      sos.sections[si] = single({z1, 0.0}, {p1, 0.0});
    } else if (p.size() + 1 == z.size() && !is_real(p1) && n_real_p == 1 && n_real_z == 1) {
      const cd z1 = take(z, nearest(z, p1, Which::complex));
      sos.sections[si] = single({z1, std::conj(z1)}, {p1, std::conj(p1)});
    } else {
      cd p2;
      if (is_real(p1)) {
        std::vector<std::size_t> reals;
        for (std::size_t i = 0; i < p.size(); ++i)
          if (is_real(p[i])) reals.push_back(i);
        p2 = take(p, idx_worst(p, reals));
      } else {
        p2 = std::conj(p1);
      }
      if (!z.empty()) {
        const cd z1 = take(z, nearest(z, p1, Which::any));
        if (!is_real(z1)) {
          sos.sections[si] = single({z1, std::conj(z1)}, {p1, p2});
        } else if (!z.empty()) {
          const cd z2 = take(z, nearest(z, p1, Which::real));
          sos.sections[si] = single({z1, z2}, {p1, p2});
        } else {
          sos.sections[si] = single({z1}, {p1, p2});
        }
      } else {
        sos.sections[si] = single({}, {p1, p2});
      }
    }
  }
  for (int i = 0; i < 3; ++i) sos.sections[0][static_cast<std::size_t>(i)] *= zpk.k;
  return sos;
}

}  // namespace

std::complex<double> Sos::response(double f_hz, double fs_hz) const {
  const cd zinv = std::exp(cd(0.0, -2.0 * M_PI * f_hz / fs_hz));
  cd h = 1.0;
  for (const auto& s : sections)
    h *= (s[0] + s[1] * zinv + s[2] * zinv * zinv) / (s[3] + s[4] * zinv + s[5] * zinv * zinv);
  return h;
}

bool Cheby1Spec::is_valid(double fs_hz, std::string* why) const {
  OptionsCheck c("Cheby1Spec", why);
  if (!c.require(fs_hz > 0.0, "fs_hz", fs_hz, "sampling rate > 0 Hz") ||
      !c.require(order >= 1 && order <= 12, "order", order, "order in 1..12") ||
      !c.require(ripple_db > 0.0, "ripple_db", ripple_db, "ripple_db > 0"))
    return false;
  const double nyq = fs_hz / 2.0;
  const bool use_low = band != BandType::lowpass, use_high = band != BandType::highpass;
  return (!use_low || c.require(low_hz > 0.0 && low_hz < nyq, "low_hz", low_hz, "low_hz in (0, fs/2 = " + num(nyq) + ") Hz")) &&
         (!use_high || c.require(high_hz > 0.0 && high_hz < nyq, "high_hz", high_hz,
                                 "high_hz in (0, fs/2 = " + num(nyq) + ") Hz (reduce the time step or the band edge)")) &&
         (band != BandType::bandpass || c.require(low_hz < high_hz, "low_hz", low_hz, "low_hz < high_hz = " + num(high_hz)));
}

Sos cheby1(const Cheby1Spec& spec, double fs_hz) {
  std::string why;
  if (!spec.is_valid(fs_hz, &why)) throw InputError("Chebyshev filter: " + why);
  // Pre-warp with SciPy's internal fs = 2 on normalised frequencies.
  const double fs = 2.0;
  auto warp = [&](double f_hz) {
    const double wn = 2.0 * f_hz / fs_hz;
    return 2.0 * fs * std::tan(M_PI * wn / fs);
  };
  Zpk proto = cheb1ap(spec.order, spec.ripple_db);
  Zpk analog;
  switch (spec.band) {
    case BandType::lowpass: analog = lp2lp(proto, warp(spec.high_hz)); break;
    case BandType::highpass: analog = lp2hp(proto, warp(spec.low_hz)); break;
    case BandType::bandpass: {
      const double w0 = warp(spec.low_hz), w1 = warp(spec.high_hz);
      analog = lp2bp(proto, std::sqrt(w0 * w1), w1 - w0);
      break;
    }
  }
  return zpk2sos(bilinear(analog, fs));
}

namespace {
// One sample u through section c from its state (z0, z1), transposed direct form II: u becomes
// the section's output. Every pass of the filter takes it (one formula: the same numbers), on a
// double or on four records' values in vector lanes (T = Four: always inlined, so the AVX2 caller
// builds it with its instructions, and through references, no vector returned).
template <class T>
VIADUCT_ALWAYS_INLINE void section_step(const Section& c, T& u, T& z0, T& z1) {
  const T yi = c[0] * u + z0;
  z0 = c[1] * u - c[4] * yi + z1;
  z1 = c[2] * u - c[5] * yi;
  u = yi;
}

// K records y[k] (n[k] samples each) in place through the NS sections c from the states z[k]
// (z0, z1 per section), sample by sample; z[k] ends as the final state. Each section's recurrence
// is a chain of four dependent operations a sample; with the states in registers the sections'
// chains overlap in the processor (a section at a time over the whole record they ran one after
// another: the same operations on the same numbers, NS times as long), and so do K records'
// (their common length in lock-step, then each one's rest alone; per record the same operations
// in the same order).
#ifdef VIADUCT_HAVE_AVX2_VARIANT
typedef double Four __attribute__((vector_size(4 * sizeof(double)), __may_alias__));
// Four records' common length through the NS sections as sos_cascade_many, the records in the
// lanes of one AVX2 vector: section_step on each lane (no contraction, -ffp-contract=off), so the
// same numbers; a quarter of the instructions (the
// filter was 5.7 % of the 31-station sweep on one thread in perf, the scalar code's four records
// limited by the instructions rather than the recurrence's latency).
template <std::size_t NS>
VIADUCT_TARGET_AVX2 void sos_cascade_four(const Section* c, double* const* y, Index common, double (&zz)[4][2 * NS]) {
  Four z0[NS], z1[NS];
  for (std::size_t s = 0; s < NS; ++s) {
    z0[s] = Four{zz[0][2 * s], zz[1][2 * s], zz[2][2 * s], zz[3][2 * s]};
    z1[s] = Four{zz[0][2 * s + 1], zz[1][2 * s + 1], zz[2][2 * s + 1], zz[3][2 * s + 1]};
  }
  for (Index i = 0; i < common; ++i) {
    Four u = {y[0][i], y[1][i], y[2][i], y[3][i]};
    for (std::size_t s = 0; s < NS; ++s) section_step(c[s], u, z0[s], z1[s]);
    for (std::size_t k = 0; k < 4; ++k) y[k][i] = u[k];
  }
  for (std::size_t s = 0; s < NS; ++s)
    for (std::size_t k = 0; k < 4; ++k) zz[k][2 * s] = z0[s][k], zz[k][2 * s + 1] = z1[s][k];
}
#endif

template <std::size_t NS, std::size_t K>
void sos_cascade_many(const Section* c, double* const* y, const Index* n, double* const* z) {
  Index common = n[0];
  for (std::size_t k = 1; k < K; ++k) common = std::min(common, n[k]);
  double zz[K][2 * NS];
  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t e = 0; e < 2 * NS; ++e) zz[k][e] = z[k][e];
  Index i0 = 0;  // samples already through (the four-lane vector path)
#ifdef VIADUCT_HAVE_AVX2_VARIANT
  if constexpr (K == 4) {
    if (simd_level() >= Simd::avx2) {
      sos_cascade_four<NS>(c, y, common, zz);
      i0 = common;
    }
  }
#endif
  for (Index i = i0; i < common; ++i) {
    double u[K];
    for (std::size_t k = 0; k < K; ++k) u[k] = y[k][i];
    for (std::size_t s = 0; s < NS; ++s)
      for (std::size_t k = 0; k < K; ++k) section_step(c[s], u[k], zz[k][2 * s], zz[k][2 * s + 1]);
    for (std::size_t k = 0; k < K; ++k) y[k][i] = u[k];
  }
  for (std::size_t k = 0; k < K; ++k) {
    for (std::size_t e = 0; e < 2 * NS; ++e) z[k][e] = zz[k][e];
    if constexpr (K > 1) {
      double* rest = y[k] + common;
      const Index n_rest = n[k] - common;
      sos_cascade_many<NS, 1>(c, &rest, &n_rest, &z[k]);
    }
  }
}

// Records y[0 … K) in place through every section (chunks of up to four, as sosfilt), from the
// states z[k] (2 per section) to their final states.
template <std::size_t K>
void sosfilt_many(const Sos& sos, double* const* y, const Index* n, double* const* z) {
  const std::size_t ns = sos.n_sections();
  const Section* c = sos.sections.data();
  for (std::size_t s0 = 0; s0 < ns; s0 += 4) {
    double* zs[K];
    for (std::size_t k = 0; k < K; ++k) zs[k] = z[k] + 2 * s0;
    switch (std::min<std::size_t>(4, ns - s0)) {
      case 1: sos_cascade_many<1, K>(c + s0, y, n, zs); break;
      case 2: sos_cascade_many<2, K>(c + s0, y, n, zs); break;
      case 3: sos_cascade_many<3, K>(c + s0, y, n, zs); break;
      default: sos_cascade_many<4, K>(c + s0, y, n, zs); break;
    }
  }
}

// The cascade's state (z0, z1 per section) as one vector: the doubling's and the end-state map's.
Vector flat_state(const std::vector<std::array<double, 2>>& z) {
  Vector v(static_cast<Index>(2 * z.size()));
  for (std::size_t s = 0; s < z.size(); ++s) {
    v[static_cast<Index>(2 * s)] = z[s][0];
    v[static_cast<Index>(2 * s + 1)] = z[s][1];
  }
  return v;
}
}  // namespace

void sosfilt(const Sos& sos, const Vector& x, Vector& y, const std::vector<std::array<double, 2>>* zi,
             std::vector<std::array<double, 2>>* zf) {
  const std::size_t ns = sos.n_sections();
  if (zi && zi->size() != ns) throw InputError("sosfilt: zi must have one row per section");
  std::vector<double> z(2 * ns, 0.0);
  for (std::size_t s = 0; s < ns && zi; ++s) z[2 * s] = (*zi)[s][0], z[2 * s + 1] = (*zi)[s][1];
  y = x;
  // One record through sosfilt_many (up to four sections at a time; filter.order 3 band-pass:
  // three).
  double* yp = y.data();
  double* zp = z.data();
  const Index n = y.size();
  sosfilt_many<1>(sos, &yp, &n, &zp);
  if (zf) {
    zf->assign(ns, {0.0, 0.0});
    for (std::size_t s = 0; s < ns; ++s) (*zf)[s] = {z[2 * s], z[2 * s + 1]};
  }
}

std::vector<std::array<double, 2>> sosfilt_zi(const Sos& sos) {
  std::vector<std::array<double, 2>> zi(sos.n_sections());
  double scale = 1.0;
  for (std::size_t s = 0; s < sos.n_sections(); ++s) {
    const Section& c = sos.sections[s];
    const double b0 = c[0] / c[3], b1 = c[1] / c[3], b2 = c[2] / c[3];
    const double a1 = c[4] / c[3], a2 = c[5] / c[3];
    // lfilter_zi: (I - companion(a)ᵀ) zi = b[1:] - a[1:] b0
    Eigen::Matrix2d A;
    A << 1.0 + a1, -1.0, a2, 1.0;
    const Eigen::Vector2d B(b1 - a1 * b0, b2 - a2 * b0);
    const Eigen::Vector2d z = A.partialPivLu().solve(B);
    zi[s] = {scale * z[0], scale * z[1]};
    scale *= (c[0] + c[1] + c[2]) / (c[3] + c[4] + c[5]);
  }
  return zi;
}

std::size_t default_padlen(const Sos& sos) {
  std::size_t nb2 = 0, na2 = 0;
  for (const auto& s : sos.sections) {
    nb2 += (s[2] == 0.0);
    na2 += (s[5] == 0.0);
  }
  return 3 * (2 * sos.n_sections() + 1 - std::min(nb2, na2));
}

FiltfiltFromRest::FiltfiltFromRest(const Sos& sos) : sos_(sos) {
  const std::size_t ns = sos.n_sections();
  if (ns == 0) return;
  using State = std::vector<std::array<double, 2>>;
  // One sample through the cascade from `z` with input u (transposed direct form II, as sosfilt).
  auto step = [&](State& z, double u) {
    for (std::size_t s = 0; s < ns; ++s) section_step(sos.sections[s], u, z[s][0], z[s][1]);
    return u;
  };
  const Index m = static_cast<Index>(2 * ns);
  // State space of one step: z' = A z + B u, output y = C z + D u.
  Matrix A(m, m), C(1, m);
  for (Index j = 0; j < m; ++j) {
    State z(ns, {0.0, 0.0});
    z[static_cast<std::size_t>(j / 2)][static_cast<std::size_t>(j % 2)] = 1.0;
    C(0, j) = step(z, 0.0);
    A.col(j) = flat_state(z);
  }
  State zb(ns, {0.0, 0.0});
  step(zb, 1.0);
  const Vector B = flat_state(zb);
  // Beyond the record the forward pass rings freely: y_{N+k} = C A^k s_N. The backward pass,
  // run from infinitely far back over those samples, arrives in W s_N with
  // W = sum_k A^k B C A^k, i.e. W = B C + A W A; doubling sums 2^i terms after i rounds.
  Matrix W = B * C, P = A;
  for (int i = 0; i < 64 && P.cwiseAbs().maxCoeff() > 1e-18; ++i) {
    W += P * W * P;
    P = P * P;
  }
  if (!W.allFinite() || P.cwiseAbs().maxCoeff() > 1e-18)
    throw InputError("zero-phase filtering: the filter is not stable (its free response does not decay)");
  W_ = std::move(W);
}

Vector FiltfiltFromRest::operator()(const Vector& x) const {
  const std::size_t ns = sos_.n_sections();
  if (x.size() == 0 || ns == 0) return x;
  Vector y;
  std::vector<std::array<double, 2>> zf;
  sosfilt(sos_, x, y, nullptr, &zf);
  const Vector w = W_ * flat_state(zf);
  std::vector<std::array<double, 2>> z1(ns);
  for (std::size_t s = 0; s < ns; ++s) z1[s] = {w[static_cast<Index>(2 * s)], w[static_cast<Index>(2 * s + 1)]};
  Vector rev = y.reverse();
  sosfilt(sos_, rev, y, &z1);
  return y.reverse();
}

std::vector<Vector> FiltfiltFromRest::operator()(const std::vector<Vector>& xs) const {
  constexpr std::size_t K = 4;
  const std::size_t ns = sos_.n_sections();
  std::vector<Vector> out(xs.size());
  std::size_t i = 0;
  for (; ns > 0 && i + K <= xs.size(); i += K) {
    double* y[K];
    Index n[K];
    std::vector<double> z(K * 2 * ns, 0.0);
    double* zp[K];
    for (std::size_t k = 0; k < K; ++k) {
      out[i + k] = xs[i + k];
      y[k] = out[i + k].data(), n[k] = out[i + k].size(), zp[k] = z.data() + k * 2 * ns;
    }
    sosfilt_many<K>(sos_, y, n, zp);  // forward, from rest
    // The backward pass's start (as operator(): W times the forward pass's end state), then the
    // records reversed through the cascade again and reversed back.
    for (std::size_t k = 0; k < K; ++k) {
      Vector zf(static_cast<Index>(2 * ns));  // as flat_state gives it to operator()
      for (Index e = 0; e < zf.size(); ++e) zf[e] = zp[k][e];
      const Vector w = W_ * zf;
      for (Index e = 0; e < w.size(); ++e) zp[k][e] = w[e];
      out[i + k].reverseInPlace();
    }
    sosfilt_many<K>(sos_, y, n, zp);
    for (std::size_t k = 0; k < K; ++k) out[i + k].reverseInPlace();
  }
  for (; i < xs.size(); ++i) out[i] = (*this)(xs[i]);
  return out;
}

Vector filtfilt_from_rest(const Sos& sos, const Vector& x) {
  if (x.size() == 0 || sos.n_sections() == 0) return x;
  return FiltfiltFromRest(sos)(x);
}

Vector sosfiltfilt(const Sos& sos, Eigen::Ref<const Vector> x) {
  const std::size_t padlen = default_padlen(sos);
  const Index n = x.size();
  if (static_cast<std::size_t>(n) <= padlen)
    throw InputError("signal of " + std::to_string(n) + " samples is too short for zero-phase filtering (needs more than " +
                     std::to_string(padlen) + ")");
  const Index p = static_cast<Index>(padlen);
  Vector ext(n + 2 * p);
  for (Index i = 0; i < p; ++i) ext[i] = 2.0 * x[0] - x[p - i];
  ext.segment(p, n) = x;
  for (Index i = 0; i < p; ++i) ext[p + n + i] = 2.0 * x[n - 1] - x[n - 2 - i];
  const auto zi = sosfilt_zi(sos);
  auto scaled = [&](double x0) {
    auto z = zi;
    for (auto& r : z) {
      r[0] *= x0;
      r[1] *= x0;
    }
    return z;
  };
  Vector y;
  auto z0 = scaled(ext[0]);
  sosfilt(sos, ext, y, &z0);
  Vector rev = y.reverse();
  auto z1 = scaled(rev[0]);
  sosfilt(sos, rev, y, &z1);
  return y.reverse().segment(p, n);
}

}  // namespace viaduct::signal

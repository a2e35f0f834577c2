// FFTW behind RAII: one plan per transform size, made under a lock, executed by any thread.
#include <fftw3.h>

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/resample.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::signal {

namespace {

struct PlanDeleter {
  void operator()(fftw_plan_s* p) const {
    if (p) fftw_destroy_plan(p);
  }
};
using Plan = std::unique_ptr<fftw_plan_s, PlanDeleter>;

// Plans for out-of-place r2c (forward) or c2r (inverse) transforms of size n on unaligned arrays, so that one plan serves
// any input and output buffers through fftw_execute_dft_r2c (the thread-safe new-array call).
class PlanCache {
 public:
  fftw_plan get(int n, bool inverse) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto& plans = inverse ? inverse_ : forward_;
    auto it = plans.find(n);
    if (it != plans.end()) return it->second.get();
    std::vector<double> real(static_cast<std::size_t>(n));
    std::vector<fftw_complex> cplx(static_cast<std::size_t>(n / 2 + 1));
    // c2r destroys its input unless told otherwise; keep callers' arrays intact.
    Plan p(inverse ? fftw_plan_dft_c2r_1d(n, cplx.data(), real.data(), FFTW_ESTIMATE | FFTW_UNALIGNED | FFTW_PRESERVE_INPUT)
                   : fftw_plan_dft_r2c_1d(n, real.data(), cplx.data(), FFTW_ESTIMATE | FFTW_UNALIGNED));
    if (!p) throw SolverError("FFTW could not make a plan for n = " + std::to_string(n));
    return plans.emplace(n, std::move(p)).first->second.get();
  }

 private:
  std::mutex mutex_;
  std::map<int, Plan> forward_, inverse_;

 public:
  // Complex backward (unnormalised) transform of size n.
  fftw_plan get_c2c_backward(int n) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = c2c_.find(n);
    if (it != c2c_.end()) return it->second.get();
    std::vector<fftw_complex> a(static_cast<std::size_t>(n)), b(static_cast<std::size_t>(n));
    Plan p(fftw_plan_dft_1d(n, a.data(), b.data(), FFTW_BACKWARD, FFTW_ESTIMATE | FFTW_UNALIGNED));
    if (!p) throw SolverError("FFTW could not make a plan for n = " + std::to_string(n));
    return c2c_.emplace(n, std::move(p)).first->second.get();
  }

 private:
  std::map<int, Plan> c2c_;
};

PlanCache& cache() {
  static PlanCache c;
  return c;
}

}  // namespace

ComplexVector rfft(const Vector& x) {
  if (x.size() < 1) throw InputError("FFT of an empty signal");
  if (x.size() > (1 << 30)) throw InputError("FFT longer than 2^30 points");
  const int n = static_cast<int>(x.size());
  fftw_plan plan = cache().get(n, false);
  ComplexVector out(n / 2 + 1);
  static_assert(sizeof(std::complex<double>) == sizeof(fftw_complex), "layout");
  // FFTW does not modify the input of an out-of-place r2c plan made without FFTW_DESTROY_INPUT
  // (the default for r2c is to preserve it).
  fftw_execute_dft_r2c(plan, const_cast<double*>(x.data()), reinterpret_cast<fftw_complex*>(out.data()));
  return out;
}

Vector irfft(const ComplexVector& X, Index n) {
  if (n < 1 || X.size() != n / 2 + 1) throw InputError("irfft: need n/2 + 1 bins for n points");
  if (n > (1 << 30)) throw InputError("FFT longer than 2^30 points");
  fftw_plan plan = cache().get(static_cast<int>(n), true);
  Vector out(n);
  fftw_execute_dft_c2r(plan, reinterpret_cast<fftw_complex*>(const_cast<std::complex<double>*>(X.data())), out.data());
  return out / static_cast<double>(n);
}

Eigen::VectorXcd ifft(const Eigen::VectorXcd& X) {
  if (X.size() < 1) throw InputError("inverse FFT of an empty spectrum");
  if (X.size() > (1 << 30)) throw InputError("FFT longer than 2^30 points");
  fftw_plan plan = cache().get_c2c_backward(static_cast<int>(X.size()));
  Eigen::VectorXcd out(X.size());
  fftw_execute_dft(plan, reinterpret_cast<fftw_complex*>(const_cast<std::complex<double>*>(X.data())),
                   reinterpret_cast<fftw_complex*>(out.data()));
  return out / static_cast<double>(X.size());
}

double best_lag(const Vector& x, const Vector& y, Index max_lag) {
  if (x.size() == 0 || y.size() == 0) throw InputError("cross-correlation of an empty signal");
  if (max_lag < 0) throw InputError("cross-correlation: max_lag must be >= 0");
  // Zero-pad to avoid circular wrap-around, to a size FFTW likes (power of two).
  Index n = 1;
  while (n < x.size() + y.size()) n *= 2;
  Vector xp = Vector::Zero(n), yp = Vector::Zero(n);
  xp.head(x.size()) = x;
  yp.head(y.size()) = y;
  // r[lag] = Σ_j x[j] y[j + lag]
  const Vector r = irfft(rfft(xp).conjugate().cwiseProduct(rfft(yp)), n);
  auto at = [&](Index lag) { return r[(lag % n + n) % n]; };
  const Index lo = std::max<Index>(-max_lag, -(x.size() - 1)), hi = std::min<Index>(max_lag, y.size() - 1);
  Index best = lo;
  for (Index lag = lo; lag <= hi; ++lag)
    if (at(lag) > at(best)) best = lag;
  double d = 0.0;
  if (best > lo && best < hi) {
    const double a = at(best - 1), b = at(best), c = at(best + 1);
    const double den = a - 2 * b + c;
    if (den < 0) d = std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
  }
  return static_cast<double>(best) + d;
}

}  // namespace viaduct::signal

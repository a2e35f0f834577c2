// FFTW behind RAII: one plan per transform size, made under a lock, executed by any thread.
#include <fftw3.h>

#include <map>
#include <memory>
#include <mutex>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/spectrum.hpp"

namespace viaduct::signal {

namespace {

struct PlanDeleter {
  void operator()(fftw_plan_s* p) const {
    if (p) fftw_destroy_plan(p);
  }
};
using Plan = std::unique_ptr<fftw_plan_s, PlanDeleter>;

// Plans for out-of-place r2c transforms of size n on unaligned arrays, so that one plan serves
// any input and output buffers through fftw_execute_dft_r2c (the thread-safe new-array call).
class PlanCache {
 public:
  fftw_plan get(int n) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = plans_.find(n);
    if (it != plans_.end()) return it->second.get();
    std::vector<double> in(static_cast<std::size_t>(n));
    std::vector<fftw_complex> out(static_cast<std::size_t>(n / 2 + 1));
    Plan p(fftw_plan_dft_r2c_1d(n, in.data(), out.data(), FFTW_ESTIMATE | FFTW_UNALIGNED));
    if (!p) throw SolverError("FFTW could not make a plan for n = " + std::to_string(n));
    return plans_.emplace(n, std::move(p)).first->second.get();
  }

 private:
  std::mutex mutex_;
  std::map<int, Plan> plans_;
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
  fftw_plan plan = cache().get(n);
  ComplexVector out(n / 2 + 1);
  static_assert(sizeof(std::complex<double>) == sizeof(fftw_complex), "layout");
  // FFTW does not modify the input of an out-of-place r2c plan made without FFTW_DESTROY_INPUT
  // (the default for r2c is to preserve it).
  fftw_execute_dft_r2c(plan, const_cast<double*>(x.data()), reinterpret_cast<fftw_complex*>(out.data()));
  return out;
}

}  // namespace viaduct::signal

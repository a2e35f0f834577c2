#pragma once
// What the Python package's C++ sources share (python/viaduct_py.cpp, viaduct_ident.cpp).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "viaduct/core/cancel.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/log.hpp"
#include "viaduct/core/types.hpp"

namespace viaduct_py {

namespace py = pybind11;
using viaduct::Index;
using viaduct::InputError;
using viaduct::Matrix;
using viaduct::Vector;
using ContiguousArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A vector handed to numpy without a copy: moved to the heap, freed with the array.
inline py::array_t<double> to_numpy(Vector&& v) {
  auto* p = new Vector(std::move(v));
  py::capsule owner(p, [](void* q) { delete static_cast<Vector*>(q); });
  return py::array_t<double>({p->size()}, {static_cast<py::ssize_t>(sizeof(double))}, p->data(), owner);
}
inline py::array_t<double> to_numpy(std::vector<double>&& v) {
  auto* p = new std::vector<double>(std::move(v));
  py::capsule owner(p, [](void* q) { delete static_cast<std::vector<double>*>(q); });
  return py::array_t<double>({static_cast<py::ssize_t>(p->size())}, {static_cast<py::ssize_t>(sizeof(double))}, p->data(), owner);
}

// A matrix handed to numpy without a copy: moved to the heap, seen as a Fortran-ordered array
// (Eigen's column-major storage), freed with it. Complex matrices need pybind11/complex.h.
template <class M>
py::array_t<typename M::Scalar> matrix_to_numpy(M&& m) {
  using Owned = std::decay_t<M>;
  auto* p = new Owned(std::forward<M>(m));
  py::capsule owner(p, [](void* q) { delete static_cast<Owned*>(q); });
  const auto rows = static_cast<py::ssize_t>(p->rows()), cols = static_cast<py::ssize_t>(p->cols());
  const auto s = static_cast<py::ssize_t>(sizeof(typename M::Scalar));
  return py::array_t<typename M::Scalar>({rows, cols}, {s, s * rows}, p->data(), owner);
}

// A 1-D float64 array as an Eigen vector: in place when contiguous (any other array is converted
// by numpy first, and `keep` holds the converted one).
inline Eigen::Map<const Vector> view(const py::handle& x, ContiguousArray& keep,
                              const char* what) {
  // numpy would cast a complex array to its real part, silently (issue #36): refused.
  const py::array given = py::array::ensure(x);
  if (given && given.dtype().kind() == 'c')
    throw InputError(std::string(what) + ": a complex array; pass its real part, magnitude or phase explicitly");
  keep = ContiguousArray::ensure(x);
  if (!keep) throw InputError(std::string(what) + ": expected an array of numbers");
  if (keep.ndim() != 1) throw InputError(std::string(what) + ": expected a 1-D array, got " + std::to_string(keep.ndim()) + " dimensions");
  return Eigen::Map<const Vector>(keep.data(), keep.shape(0));
}

// Runs `f` on a worker thread with `cancel` as its cancellation flag (viaduct/core/cancel.hpp:
// this call's computations and no other's); the calling thread reports progress(done, total) and
// turns Ctrl-C, or an exception out of the progress callback (KeyboardInterrupt raised in it
// included), into `cancel`, then rethrows it once `f` has stopped: a cut call always raises.
template <class F>
auto interruptible(F f, const py::object& progress, const std::atomic<std::size_t>& done, const std::atomic<std::size_t>& total,
                   std::atomic<bool>& cancel) -> decltype(f()) {
  auto result = std::async(std::launch::async, [f = std::move(f), &cancel]() mutable {
    const viaduct::CancelScope scope(&cancel);
    return f();
  });
  std::size_t shown = 0;
  auto finish = [&] {
    cancel = true;  // the running time-stepping loops stop, a sweep skips the cases not started
    py::gil_scoped_release nogil;
    result.wait();
  };
  for (;;) {
    bool ready = false;
    {
      py::gil_scoped_release nogil;
      ready = result.wait_for(std::chrono::milliseconds(100)) == std::future_status::ready;
    }
    if (PyErr_CheckSignals() != 0) {
      finish();
      throw py::error_already_set();
    }
    if (!progress.is_none() && done.load() != shown) {
      shown = done.load();
      try {
        progress(shown, total.load());
      } catch (...) {
        finish();
        throw;
      }
    }
    if (ready) return result.get();
  }
}

// A long call's state as the waiting thread sees it: cases done of total (set from any thread by
// the workflow's progress callback, sink()) and the call's cancellation flag.
struct CallState {
  std::atomic<std::size_t> done{0}, total{0};
  std::atomic<bool> cancel{false};
  explicit CallState(std::size_t n_total = 0) : total(n_total) {}
  viaduct::ProgressSink sink() {
    return [this](std::size_t d, std::size_t n) {
      done = d;
      total = n;
    };
  }
};
template <class F>
auto interruptible(F f, const py::object& progress, CallState& state) -> decltype(f()) {
  return interruptible(std::move(f), progress, state.done, state.total, state.cancel);
}

// --threads as the CLI takes it: 0 is every core.
inline int threads_of(int threads) {
  if (threads < 0) throw InputError("threads must be >= 0");
  return threads == 0 ? static_cast<int>(std::max(1u, std::thread::hardware_concurrency())) : threads;
}

/// The identification functions (frf, modal_fit, decay, peaks, identify_speed).
void bind_ident(py::module_& m);
/// Model updating (fit).
void bind_fit(py::module_& m);

}  // namespace viaduct_py

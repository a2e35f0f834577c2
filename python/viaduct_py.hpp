#pragma once
// What the Python package's C++ sources share (python/viaduct_py.cpp, viaduct_ident.cpp).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "viaduct/core/error.hpp"
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

// A 1-D float64 array as an Eigen vector: in place when contiguous (any other array is converted
// by numpy first, and `keep` holds the converted one).
inline Eigen::Map<const Vector> view(const py::handle& x, ContiguousArray& keep,
                              const char* what) {
  keep = ContiguousArray::ensure(x);
  if (!keep) throw InputError(std::string(what) + ": expected an array of numbers");
  if (keep.ndim() != 1) throw InputError(std::string(what) + ": expected a 1-D array, got " + std::to_string(keep.ndim()) + " dimensions");
  return Eigen::Map<const Vector>(keep.data(), keep.shape(0));
}

/// The identification functions (frf, modal_fit, decay).
void bind_ident(py::module_& m);

}  // namespace viaduct_py

#pragma once
// The contacts of every wheel at one time, read from a ContactPath (private to src/solve: the
// coupled kernels share it).

#include <cmath>
#include <string>
#include <vector>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/solve/coupled.hpp"

namespace viaduct::solve::detail {

// The contacts of every wheel at one time.
struct Contacts {
  std::vector<std::vector<Index>> dof;
  std::vector<std::vector<double>> weight;
  Vector r;
  explicit Contacts(std::size_t nw) : dof(nw), weight(nw), r(Vector::Zero(static_cast<Index>(nw))) {}
  void read(const ContactPath& path, double t, Index n_struct) {
    for (std::size_t w = 0; w < dof.size(); ++w) {
      double rw = 0.0;
      path.contact(w, t, dof[w], weight[w], rw);
      if (dof[w].size() != weight[w].size())
        throw InputError("ContactPath: wheel " + std::to_string(w) + " has " + std::to_string(dof[w].size()) + " DOFs and " +
                         std::to_string(weight[w].size()) + " weights");
      for (Index d : dof[w])
        if (d < 0 || d >= n_struct)
          throw InputError("ContactPath: wheel " + std::to_string(w) + " touches DOF " + std::to_string(d) +
                           ", outside the structure's " + std::to_string(n_struct));
      if (!std::isfinite(rw)) throw InputError("ContactPath: non-finite irregularity under wheel " + std::to_string(w) + " at t = " + format_number(t, 6) + " s");
      r[static_cast<Index>(w)] = rw;
    }
  }
  template <class V>
  double rail(std::size_t w, const V& u) const {
    double y = 0.0;
    for (std::size_t q = 0; q < dof[w].size(); ++q) y += weight[w][q] * u[dof[w][q]];
    return y;
  }
};

}  // namespace viaduct::solve::detail

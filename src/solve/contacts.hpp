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
  // Rigid wheels (ContactPath::contact_rates): the weights' and the irregularity's time derivatives.
  std::vector<std::vector<double>> dweight, ddweight;
  Vector dr, ddr;
  // Reads the rates of the wheels with rigid[w], after read() at the same t.
  void read_rates(const ContactPath& path, double t, const std::vector<bool>& rigid) {
    if (dweight.size() != dof.size()) {
      dweight.resize(dof.size());
      ddweight.resize(dof.size());
      dr = ddr = Vector::Zero(static_cast<Index>(dof.size()));
    }
    for (std::size_t w = 0; w < dof.size(); ++w) {
      if (!rigid[w]) continue;
      double r1 = 0.0, r2 = 0.0;
      if (!path.contact_rates(w, t, dweight[w], ddweight[w], r1, r2))
        throw InputError("a rigid contact needs the rates of the rail under the wheel, which this contact path does not give");
      if (dweight[w].size() != dof[w].size() || ddweight[w].size() != dof[w].size())
        throw InputError("ContactPath: wheel " + std::to_string(w) + "'s rates do not match its weights");
      dr[static_cast<Index>(w)] = r1;
      ddr[static_cast<Index>(w)] = r2;
    }
  }
  template <class V>
  double rate(std::size_t w, const V& u, int order) const {
    const auto& wt = order == 1 ? dweight[w] : ddweight[w];
    double y = 0.0;
    for (std::size_t q = 0; q < dof[w].size(); ++q) y += wt[q] * u[dof[w][q]];
    return y;
  }
  template <class V>
  double rail(std::size_t w, const V& u) const {
    double y = 0.0;
    for (std::size_t q = 0; q < dof[w].size(); ++q) y += weight[w][q] * u[dof[w][q]];
    return y;
  }
};

}  // namespace viaduct::solve::detail

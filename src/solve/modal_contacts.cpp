#include <string>

#include "viaduct/core/error.hpp"
#include "viaduct/solve/modal.hpp"

namespace viaduct::solve {

namespace {

// A structure's contacts in the coordinates of a reduction built for the coupled kernels: a rail
// point's weights on every mode, and the dropped modes' flexibility between the wheels when the
// reduction has the static correction.
class ModalContactPath : public ContactPath {
 public:
  ModalContactPath(const ContactPath& full, const ModalReduction& r, std::size_t n_wheels)
      : full_(full), phi_(r.shapes()), r_(r), fd_(n_wheels), fw_(n_wheels) {
    if (!r.coupled()) throw InputError("modal contacts: the reduction was not built for the coupled vehicle kernels");
  }
  std::vector<double> breaks(double t_end) const override { return full_.breaks(t_end); }
  void contact(std::size_t w, double t, std::vector<Index>& dof, std::vector<double>& weight, double& r) const override {
    full_.contact(w, t, d_, w_, r);
    if (r_.static_correction()) {  // the contact DOFs' rows of wheel w, for residual_flexibility()
      fd_[w].clear();
      fw_[w] = w_;
      for (const Index d : d_) {
        const Index slot = r_.contact_slot(d);
        if (slot < 0)
          throw InputError("static correction: wheel " + std::to_string(w) + " touches DOF " + std::to_string(d) +
                           ", which is not on the structure's load path");
        fd_[w].push_back(slot);
      }
    }
    dof.clear();
    weight.clear();
    if (d_.empty()) return;
    const Index m = phi_.cols();
    dof.resize(static_cast<std::size_t>(m));
    weight.assign(static_cast<std::size_t>(m), 0.0);
    for (Index j = 0; j < m; ++j) {
      dof[static_cast<std::size_t>(j)] = j;
      double s = 0.0;
      for (std::size_t q = 0; q < d_.size(); ++q) s += w_[q] * phi_(d_[q], j);
      weight[static_cast<std::size_t>(j)] = s;
    }
  }
  // The full path's rates projected on the modes, as contact() projects its weights.
  bool contact_rates(std::size_t w, double t, std::vector<double>& dweight, std::vector<double>& ddweight, double& dr,
                     double& ddr) const override {
    double r = 0.0;
    full_.contact(w, t, d_, w_, r);
    if (!full_.contact_rates(w, t, dw_, ddw_, dr, ddr)) return false;
    dweight.clear();
    ddweight.clear();
    if (d_.empty()) return true;
    const Index m = phi_.cols();
    dweight.assign(static_cast<std::size_t>(m), 0.0);
    ddweight.assign(static_cast<std::size_t>(m), 0.0);
    for (Index j = 0; j < m; ++j)
      for (std::size_t q = 0; q < d_.size(); ++q) {
        dweight[static_cast<std::size_t>(j)] += dw_[q] * phi_(d_[q], j);
        ddweight[static_cast<std::size_t>(j)] += ddw_[q] * phi_(d_[q], j);
      }
    return true;
  }
  bool residual_flexibility(double, Matrix& F) const override {
    if (!r_.static_correction()) return false;
    const Matrix& R = r_.contact_residual();
    const Index nw = static_cast<Index>(fd_.size());
    F.setZero(nw, nw);
    for (Index a = 0; a < nw; ++a)
      for (Index b = 0; b <= a; ++b) {
        const auto &da = fd_[static_cast<std::size_t>(a)], &db = fd_[static_cast<std::size_t>(b)];
        const auto &wa = fw_[static_cast<std::size_t>(a)], &wb = fw_[static_cast<std::size_t>(b)];
        double f = 0.0;
        for (std::size_t i = 0; i < da.size(); ++i)
          for (std::size_t j = 0; j < db.size(); ++j) f += wa[i] * wb[j] * R(da[i], db[j]);
        F(a, b) = F(b, a) = f;
      }
    return true;
  }

 private:
  const ContactPath& full_;
  const Matrix& phi_;
  const ModalReduction& r_;
  mutable std::vector<Index> d_;
  mutable std::vector<double> w_, dw_, ddw_;
  mutable std::vector<std::vector<Index>> fd_;   // per wheel: rows of the contact residual under it
  mutable std::vector<std::vector<double>> fw_;  // and their weights
};

}  // namespace

std::unique_ptr<ContactPath> modal_contacts(const ContactPath& full, const ModalReduction& r, std::size_t n_wheels) {
  return std::make_unique<ModalContactPath>(full, r, n_wheels);
}

}  // namespace viaduct::solve

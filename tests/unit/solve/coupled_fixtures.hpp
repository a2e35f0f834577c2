#pragma once
// Fixtures shared by the coupled kernels' unit tests (test_coupled.cpp, test_coupled_ida.cpp).

#include <vector>

#include "viaduct/solve/coupled.hpp"
#include "viaduct/solve/second_order_system.hpp"

namespace viaduct::coupled_fixtures {

// A wheel fixed on DOF 0 of the structure with weight w (the rail under it does not move along);
// the rail there steps by r at t_r (a break for the adaptive kernel).
class FixedContact : public solve::ContactPath {
 public:
  explicit FixedContact(double w, double r = 0.0, double t_r = 1e9) : w_(w), r_(r), t_r_(t_r) {}
  void contact(std::size_t, double t, std::vector<Index>& dof, std::vector<double>& weight, double& r) const override {
    dof.assign(1, 0);
    weight.assign(1, w_);
    r = t >= t_r_ ? r_ : 0.0;
  }
  std::vector<double> breaks(double) const override { return {t_r_}; }
  // The weight is constant; the rail's step (at t_r) has no rate between samples.
  bool contact_rates(std::size_t, double, std::vector<double>& dweight, std::vector<double>& ddweight, double& dr,
                     double& ddr) const override {
    dweight.assign(1, 0.0);
    ddweight.assign(1, 0.0);
    dr = ddr = 0.0;
    return true;
  }

 private:
  double w_, r_, t_r_;
};

// The same two masses assembled as one system: u (structure), z (vehicle), the contact spring
// between w·u and z, the static load on the structure, the step r in the rail as a force pair.
class Assembled : public solve::SecondOrderSystem {
 public:
  Assembled(double ms, double ks, double cs, double mv, double kc, double w, double P0, double r, double t_r)
      : P0_(P0), w_(w), kc_(kc), r_(r), t_r_(t_r) {
    M_.resize(2, 2), C_.resize(2, 2), K_.resize(2, 2);
    M_.insert(0, 0) = ms;
    M_.insert(1, 1) = mv;
    C_.insert(0, 0) = cs;
    K_.insert(0, 0) = ks + kc * w * w;
    K_.insert(0, 1) = -kc * w;
    K_.insert(1, 0) = -kc * w;
    K_.insert(1, 1) = kc;
  }
  const SparseMatrix& mass() const override { return M_; }
  const SparseMatrix& damping() const override { return C_; }
  const SparseMatrix& stiffness() const override { return K_; }
  void force(double t, Vector& f) const override {
    const double r = t >= t_r_ ? r_ : 0.0;  // p = kc (z − w u − r): the rail's step pushes the wheel up
    f[0] = w_ * P0_ - w_ * kc_ * r;
    f[1] = kc_ * r;
  }
  std::vector<double> discontinuities(double) const override { return {t_r_}; }

 private:
  SparseMatrix M_, C_, K_;
  double P0_, w_, kc_, r_, t_r_;
};

// A 1 × 1 structure (M = K = 1, no damping) for wheels that roll on rigid ground beside it.
struct Untouched {
  SparseMatrix M{1, 1}, C{1, 1}, K{1, 1};
  Untouched() {
    M.insert(0, 0) = 1.0;
    K.insert(0, 0) = 1.0;
  }
};

// One wheel of mass m (no suspension) pressing P0 on a contact of stiffness k.
inline solve::LinearVehicle one_wheel(double m, double P0, double k) {
  solve::LinearVehicle veh;
  veh.M = Matrix::Constant(1, 1, m);
  veh.C = Matrix::Zero(1, 1);
  veh.K = Matrix::Zero(1, 1);
  veh.wheel_dof = {0};
  veh.static_load = Vector::Constant(1, P0);
  veh.contact_stiffness = Vector::Constant(1, k);
  return veh;
}

}  // namespace viaduct::coupled_fixtures

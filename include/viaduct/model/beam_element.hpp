#pragma once
/// \file Two-node Bernoulli–Euler (Hermite cubic) beam element. DOFs per node: deflection w
/// [m] (positive down, the direction of gravity loads) and rotation θ = dw/dx [rad].

#include <array>

#include "viaduct/core/types.hpp"

namespace viaduct::model {

using Matrix4 = Eigen::Matrix<double, 4, 4>;

/// Element stiffness for bending stiffness EI [N·m²] > 0 and length h [m] > 0.
Matrix4 beam_stiffness(double EI, double h);
/// Consistent element mass for mass per length m [kg/m] >= 0 and length h [m] > 0.
Matrix4 beam_mass(double m, double h);
/// Hermite shape functions at local coordinate xi in [0, 1] of an element of length h:
/// w(x) = N · (w0, θ0, w1, θ1).
std::array<double, 4> hermite_shape(double xi, double h);
/// Their first derivatives dN/dx [1/m, 1] at xi: w'(x) = N' · (w0, θ0, w1, θ1).
std::array<double, 4> hermite_slope(double xi, double h);
/// Their second derivatives d²N/dx² [1/m², 1/m] at xi: w''(x) = N'' · (w0, θ0, w1, θ1).
std::array<double, 4> hermite_curvature(double xi, double h);
/// Their third derivatives d³N/dx³ [1/m³, 1/m²], constant along the element: w‴ = N‴ · (w0, θ0, w1, θ1).
std::array<double, 4> hermite_third(double h);

}  // namespace viaduct::model

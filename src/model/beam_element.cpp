#include "viaduct/model/beam_element.hpp"

namespace viaduct::model {

Matrix4 beam_stiffness(double EI, double h) {
  const double h2 = h * h;
  Matrix4 k;
  k << 12, 6 * h, -12, 6 * h,        //
      6 * h, 4 * h2, -6 * h, 2 * h2,  //
      -12, -6 * h, 12, -6 * h,        //
      6 * h, 2 * h2, -6 * h, 4 * h2;
  return k * (EI / (h2 * h));
}

Matrix4 beam_mass(double m, double h) {
  const double h2 = h * h;
  Matrix4 mm;
  mm << 156, 22 * h, 54, -13 * h,        //
      22 * h, 4 * h2, 13 * h, -3 * h2,    //
      54, 13 * h, 156, -22 * h,           //
      -13 * h, -3 * h2, -22 * h, 4 * h2;
  return mm * (m * h / 420.0);
}

std::array<double, 4> hermite_shape(double xi, double h) {
  const double x2 = xi * xi, x3 = x2 * xi;
  return {1.0 - 3.0 * x2 + 2.0 * x3, h * (xi - 2.0 * x2 + x3), 3.0 * x2 - 2.0 * x3,
          h * (x3 - x2)};
}

std::array<double, 4> hermite_slope(double xi, double h) {
  const double x2 = xi * xi;
  return {(6.0 * x2 - 6.0 * xi) / h, 1.0 - 4.0 * xi + 3.0 * x2, (6.0 * xi - 6.0 * x2) / h, 3.0 * x2 - 2.0 * xi};
}

std::array<double, 4> hermite_curvature(double xi, double h) {
  return {(12.0 * xi - 6.0) / (h * h), (6.0 * xi - 4.0) / h, (6.0 - 12.0 * xi) / (h * h), (6.0 * xi - 2.0) / h};
}

std::array<double, 4> hermite_third(double h) { return {12.0 / (h * h * h), 6.0 / (h * h), -12.0 / (h * h * h), 6.0 / (h * h)}; }

}  // namespace viaduct::model

#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "viaduct/core/error.hpp"
#include "viaduct/solve/ida.hpp"

using namespace viaduct;
using namespace viaduct::solve;

namespace {
// m ü + c u̇ + k u = F0 for t < t_off (0 after; t_off <= 0: always on), reported as a
// discontinuity when `report` is set.
class Step : public SecondOrderSystem {
 public:
  Step(double m, double c, double k, double F0, double t_off, bool report) : F0_(F0), t_off_(t_off), report_(report) {
    auto one = [](double v) {
      SparseMatrix A(1, 1);
      A.insert(0, 0) = v;
      A.makeCompressed();
      return A;
    };
    M_ = one(m), C_ = one(c), K_ = one(k);
  }
  const SparseMatrix& mass() const override { return M_; }
  const SparseMatrix& damping() const override { return C_; }
  const SparseMatrix& stiffness() const override { return K_; }
  void force(double t, Vector& f) const override {
    if (throw_at_ > 0 && t > throw_at_) throw std::runtime_error("callback failure at " + std::to_string(t));
    f[0] = (t_off_ <= 0 || t < t_off_) ? F0_ : 0.0;
  }
  std::vector<double> discontinuities(double t_end) const override {
    if (report_ && t_off_ > 0 && t_off_ < t_end) return {t_off_};
    return {};
  }
  double throw_at_ = 0.0;

 private:
  SparseMatrix M_, C_, K_;
  double F0_, t_off_;
  bool report_;
};

// Step response of a damped oscillator from rest (unit mass).
double step_response(double t, double w, double z, double F0) {
  const double wd = w * std::sqrt(1 - z * z);
  return F0 / (w * w) * (1 - std::exp(-z * w * t) * (std::cos(wd * t) + z / std::sqrt(1 - z * z) * std::sin(wd * t)));
}
}  // namespace

TEST_CASE("IDA converges to the step response as the tolerance tightens") {
  const double w = 2 * M_PI * 2.0, z = 0.03;
  const Step sys(1.0, 2 * z * w, w * w, 5.0, 0.0, false);
  double prev = 1e9;
  for (double rtol : {1e-3, 1e-5, 1e-7, 1e-9}) {
    IdaOptions o;
    const TimeGrid g{0.01, 3.0};
    o.rtol = rtol;
    o.atol_disp = rtol * 1e-3;
    o.atol_vel = rtol * 1e-2;
    double err = 0.0, peak = 0.0;
    const Summary s = ida(sys, g, o, [&](Index, double t, const Vector& u, const Vector&, const Vector&) {
      err = std::max(err, std::abs(u[0] - step_response(t, w, z, 5.0)));
      peak = std::max(peak, std::abs(u[0]));
    });
    REQUIRE(s.n_samples == 301);
    REQUIRE(s.n_steps > 0);
    // Global error of an adaptive BDF: a small multiple of the tolerance (here < 100 rtol) and
    // decreasing with it.
    REQUIRE(err < 100 * rtol * peak);
    REQUIRE(err < prev);
    prev = err;
  }
}

TEST_CASE("IDA stops and restarts at a reported discontinuity") {
  // The force switches off at 0.3 s; afterwards free vibration from the state at 0.3 s.
  const double w = 2 * M_PI * 2.0, z = 0.03, t_off = 0.3;
  auto exact = [&](double t) {
    if (t <= t_off) return step_response(t, w, z, 5.0);
    return step_response(t, w, z, 5.0) - step_response(t - t_off, w, z, 5.0);  // superposition
  };
  for (bool report : {true, false}) {
    const Step sys(1.0, 2 * z * w, w * w, 5.0, t_off, report);
    IdaOptions o;
    const TimeGrid g{0.005, 1.5};
    o.rtol = 1e-8;
    o.atol_disp = 1e-12;
    o.atol_vel = 1e-10;
    double err = 0.0, peak = 0.0;
    const Summary s = ida(sys, g, o, [&](Index, double t, const Vector& u, const Vector&, const Vector&) {
      err = std::max(err, std::abs(u[0] - exact(t)));
      peak = std::max(peak, std::abs(u[0]));
    });
    if (report) {
      REQUIRE(s.n_restarts == 1);
      REQUIRE(err < 1e-6 * peak);  // the jump is not smeared
    } else {
      REQUIRE(s.n_restarts == 0);
      REQUIRE(err < 1e-3 * peak);  // IDA copes, by error-test failures around the jump
    }
  }
}

TEST_CASE("an exception thrown in the system's callback crosses IDA intact") {
  Step sys(1.0, 0.1, 100.0, 1.0, 0.0, false);
  sys.throw_at_ = 0.25;
  const IdaOptions o;
  REQUIRE_THROWS_WITH(ida(sys, TimeGrid{1e-3, 1.0}, o, nullptr), Catch::StartsWith("callback failure at 0.25"));
}

TEST_CASE("IDA: invalid options are refused and failures carry IDA's flag and message") {
  const Step sys(1.0, 0.1, 100.0, 1.0, 0.0, false);
  const TimeGrid g{1e-3, 1.0};
  IdaOptions o;
  o.rtol = 0.0;
  REQUIRE_THROWS_WITH(ida(sys, g, o, nullptr), Catch::Contains("IdaOptions::rtol = 0: violated constraint rtol in [1e-12, 0.1]"));
  o = IdaOptions{};
  o.max_order = 6;
  REQUIRE_THROWS_WITH(ida(sys, g, o, nullptr), Catch::Contains("IdaOptions::max_order = 6: violated constraint max_order in 1..5"));
  o = IdaOptions{};
  REQUIRE_THROWS_WITH(ida(sys, TimeGrid{-1.0, 1.0}, o, nullptr), Catch::Contains("TimeGrid::dt = -1"));
  // Too little work allowed per output: IDA gives up with its flag and its own message (which
  // goes into the exception, not to stderr).
  o = IdaOptions{};
  o.rtol = 1e-10;
  o.atol_disp = 1e-14;
  o.atol_vel = 1e-12;
  o.max_steps_per_output = 3;
  REQUIRE_THROWS_WITH(ida(sys, TimeGrid{0.5, 1.0}, o, nullptr), Catch::Contains("IDA_TOO_MUCH_WORK") && Catch::Contains("IDASolve"));
}

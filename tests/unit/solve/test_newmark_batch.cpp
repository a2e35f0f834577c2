#include <catch2/catch.hpp>
#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/solve/newmark.hpp"

using namespace viaduct;
using namespace viaduct::solve;

// newmark_batch must give newmark()'s answers case by case: the same scheme on the same
// factorisation, only the order of the floating-point sums differs (products and substitutions
// split into partial sums, the ordering of the factor's permutation). 1e-10 of each history's
// largest value is far above that rounding and far below any change of scheme, step, load or
// DOF mapping.
namespace {
constexpr double kRel = 1e-10;

// A chain of n masses on springs to ground and between neighbours, with dashpots that do not
// follow the stiffness (non-proportional damping), shared by every load case.
struct BatchChain {
  SparseMatrix M, C, K;
  explicit BatchChain(int n) {
    std::vector<Triplet> tm, tc, tk;
    for (int i = 0; i < n; ++i) {
      tm.emplace_back(i, i, 1.0 + 0.1 * i);
      tk.emplace_back(i, i, 2e4 + 1e3 * (i % 3));
      tc.emplace_back(i, i, i % 2 ? 5.0 : 0.5);
      if (i + 1 < n) {
        const double k = 1e4 * (1.0 + 0.2 * (i % 4)), c = 2.0 + i % 3;
        for (auto [a, b, s] : {std::tuple{i, i, 1.0}, {i + 1, i + 1, 1.0}, {i, i + 1, -1.0}, {i + 1, i, -1.0}}) {
          tk.emplace_back(a, b, s * k);
          tc.emplace_back(a, b, s * c);
        }
      }
    }
    M.resize(n, n), C.resize(n, n), K.resize(n, n);
    M.setFromTriplets(tm.begin(), tm.end());
    C.setFromTriplets(tc.begin(), tc.end());
    K.setFromTriplets(tk.begin(), tk.end());
  }
};

// A force P·sin(Ω t) moving from DOF to DOF every `hop` seconds (sparse entries, with jumps),
// or, with dense = true, the same through force() only.
class Case : public SecondOrderSystem {
 public:
  Case(const BatchChain& c, double P, double Om, double hop, bool dense) : c_(c), P_(P), Om_(Om), hop_(hop), dense_(dense) {}
  const SparseMatrix& mass() const override { return c_.M; }
  const SparseMatrix& damping() const override { return c_.C; }
  const SparseMatrix& stiffness() const override { return c_.K; }
  void force(double t, Vector& f) const override {
    f.setZero();
    f[at(t)] += value(t);
    f[(at(t) + 3) % f.size()] -= 0.5 * value(t);
  }
  bool force_entries(double t, SparseForce& out) const override {
    if (dense_) return false;
    out.clear();
    out.add(at(t), value(t));
    out.add((at(t) + 3) % c_.M.rows(), -0.5 * value(t));
    return true;
  }

 private:
  Index at(double t) const { return static_cast<Index>(std::floor(t / hop_)) % c_.M.rows(); }
  double value(double t) const { return P_ * (1.0 + std::sin(Om_ * t)); }
  const BatchChain& c_;
  double P_, Om_, hop_;
  bool dense_;
};

std::vector<Functional> outputs() {
  return {{{0}, {1.0}}, {{4, 5}, {0.5, 0.5}}, {{9}, {-2.0}}};
}

void require_same(const std::vector<BatchCase>& cases, double dt, const NewmarkOptions& opt) {
  const std::vector<Functional> out = outputs();
  const std::vector<BatchHistories> b = newmark_batch(cases, dt, opt, out);
  REQUIRE(b.size() == cases.size());
  for (std::size_t l = 0; l < cases.size(); ++l) {
    const TimeGrid g{dt, cases[l].t_end};
    Matrix d_ref, a_ref;
    const Summary s = newmark(*cases[l].system, g, opt, [&](Index k, double, const Vector& u, const Vector&,
                                                            const Vector& a) {
      if (k == 0) {
        const Index rows = g.n_steps() + 1;
        d_ref.setZero(rows, static_cast<Index>(out.size()));
        a_ref.setZero(rows, static_cast<Index>(out.size()));
      }
      for (std::size_t j = 0; j < out.size(); ++j)
        for (std::size_t q = 0; q < out[j].dof.size(); ++q) {
          d_ref(k, static_cast<Index>(j)) += out[j].weight[q] * u[out[j].dof[q]];
          a_ref(k, static_cast<Index>(j)) += out[j].weight[q] * a[out[j].dof[q]];
        }
    });
    INFO("case " << l);
    REQUIRE(b[l].summary.n_steps == s.n_steps);
    REQUIRE(b[l].disp.rows() == d_ref.rows());
    REQUIRE(d_ref.cwiseAbs().maxCoeff() > 0.0);
    REQUIRE((b[l].disp - d_ref).cwiseAbs().maxCoeff() <= kRel * d_ref.cwiseAbs().maxCoeff());
    REQUIRE((b[l].acc - a_ref).cwiseAbs().maxCoeff() <= kRel * a_ref.cwiseAbs().maxCoeff());
  }
}
}  // namespace

TEST_CASE("Newmark batch: each case as newmark() gives it, sparse and dense loads, unequal durations") {
  const BatchChain chain(12);
  const Case a(chain, 100.0, 7.0, 0.013, false), b(chain, -50.0, 31.0, 0.007, false), c(chain, 80.0, 3.0, 0.021, true);
  const NewmarkOptions opt;
  SECTION("three cases of different lengths (one lane spare)") {
    require_same({{&a, 0.5}, {&b, 0.31}, {&c, 0.4}}, 1e-3, opt);
  }
  SECTION("one case") { require_same({{&b, 0.2}}, 1e-3, opt); }
  SECTION("HHT-alpha") { require_same({{&a, 0.3}, {&b, 0.3}, {&c, 0.3}, {&a, 0.1}}, 2e-3, NewmarkOptions::hht(-0.1)); }
}

TEST_CASE("Newmark batch: refused inputs") {
  const BatchChain chain(12), other(12);
  const Case a(chain, 100.0, 7.0, 0.013, false), b(other, 100.0, 7.0, 0.013, false);
  const NewmarkOptions opt;
  const double dt = 1e-3;
  REQUIRE_THROWS_AS(newmark_batch({}, dt, opt, outputs()), InputError);
  REQUIRE_THROWS_AS(newmark_batch({{&a, 1}, {&a, 1}, {&a, 1}, {&a, 1}, {&a, 1}}, dt, opt, outputs()), InputError);
  REQUIRE_THROWS_WITH(newmark_batch({{&a, 1}, {&b, 1}}, dt, opt, outputs()), Catch::Contains("same M, C and K"));
  REQUIRE_THROWS_WITH(newmark_batch({{&a, 1}}, dt, opt, {{{12}, {1.0}}}), Catch::Contains("out of range"));
  REQUIRE_THROWS_WITH(newmark_batch({{&a, -1.0}}, dt, opt, outputs()), Catch::Contains("TimeGrid::t_end = -1"));
  REQUIRE_THROWS_WITH(newmark_batch({{&a, 1}}, 0.0, opt, outputs()), Catch::Contains("TimeGrid::dt = 0"));
  REQUIRE_THROWS_WITH(newmark_batch({{nullptr, 1}}, dt, opt, outputs()), Catch::Contains("without a system"));
  // Linear acceleration (γ = 1/2, β = 1/6) beyond its stability limit.
  NewmarkOptions lin = opt;
  lin.beta = 1.0 / 6.0;
  REQUIRE_THROWS_WITH(newmark_batch({{&a, 1}}, 0.1, lin, outputs()), Catch::Contains("conditionally stable"));
}

#include "viaduct/study/forced.hpp"

#include <Eigen/SparseLU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <random>

#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"
#include "viaduct/core/thread_pool.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/solve/integrator.hpp"
#include "viaduct/study/simulation.hpp"

namespace viaduct::study {

namespace {

using ComplexSparse = Eigen::SparseMatrix<std::complex<double>>;

const model::PointCoupling& coupling_of(const ResolvedStation& r) { return r.has_deck ? r.deck : r.rail; }

// The exciter's force F(t) distributed on the deck element's DOFs.
class ExciterSystem : public solve::SecondOrderSystem {
 public:
  ExciterSystem(const model::Structure& s, const model::PointCoupling& at, std::function<double(double)> F)
      : s_(s), at_(at), F_(std::move(F)) {}
  const SparseMatrix& mass() const override { return s_.M; }
  const SparseMatrix& damping() const override { return s_.C; }
  const SparseMatrix& stiffness() const override { return s_.K; }
  void force(double t, Vector& f) const override {
    f.setZero();
    const double v = F_(t);
    for (int i = 0; i < 4; ++i)
      if (at_.dofs[static_cast<std::size_t>(i)] >= 0) f[at_.dofs[static_cast<std::size_t>(i)]] += at_.N[static_cast<std::size_t>(i)] * v;
  }
  bool force_entries(double t, SparseForce& out) const override {
    out.clear();
    const double v = F_(t);
    for (int i = 0; i < 4; ++i)
      if (at_.dofs[static_cast<std::size_t>(i)] >= 0) out.add(at_.dofs[static_cast<std::size_t>(i)], at_.N[static_cast<std::size_t>(i)] * v);
    return true;
  }

 private:
  const model::Structure& s_;
  model::PointCoupling at_;
  std::function<double(double)> F_;
};

}  // namespace

StationSpec deck_station_at(const model::Structure& s, const std::string& name, double x_m) {
  require_finite(x_m, "position on the deck [m]");
  for (std::size_t i = 0; i < s.span_start.size(); ++i) {
    const double a = s.span_start[i], L = s.span_length[i];
    if (x_m >= a - 1e-9 && x_m <= a + L + 1e-9) {
      StationSpec sp;
      sp.name = name;
      sp.on_deck = true;
      sp.span = i;
      sp.x_local = std::clamp(x_m - a, 0.0, L);
      return sp;
    }
  }
  throw InputError("'" + name + "' at x = " + std::to_string(x_m) + " m is not on the deck (0 to " +
                   std::to_string(s.span_start.back() + s.span_length.back()) + " m)");
}

ident::Frf model_frf(const model::Structure& s, const ForcedSetup& setup, const Vector& frequency_hz, int threads,
                     const ProgressSink& progress) {
  if (frequency_hz.size() < 2) throw InputError("model FRF: at least 2 frequencies are needed");
  for (Index k = 0; k < frequency_hz.size(); ++k) {
    if (!(frequency_hz[k] > 0.0) || !std::isfinite(frequency_hz[k])) throw InputError("model FRF: frequencies must be > 0 and finite");
    if (k > 0 && !(frequency_hz[k] > frequency_hz[k - 1])) throw InputError("model FRF: frequencies must increase");
  }
  const auto stations = resolve_stations(s, setup.responses);
  const model::PointCoupling at = model::point_on(s.deck_elements, setup.force_x_m, "deck (exciter position)");
  Eigen::VectorXcd F = Eigen::VectorXcd::Zero(s.n_dofs);
  for (int i = 0; i < 4; ++i)
    if (at.dofs[static_cast<std::size_t>(i)] >= 0) F[at.dofs[static_cast<std::size_t>(i)]] += at.N[static_cast<std::size_t>(i)];
  if (F.cwiseAbs().maxCoeff() == 0.0) throw InputError("model FRF: the exciter sits on a fixed support: it does no work");
  const ComplexSparse Kc = s.K.cast<std::complex<double>>(), Mc = s.M.cast<std::complex<double>>(),
                      Cc = s.C.cast<std::complex<double>>();
  ident::Frf r;
  r.frequency_hz = frequency_hz;
  r.h.resize(frequency_hz.size(), static_cast<Index>(stations.size()));
  for (const auto& st : stations) {
    r.responses.push_back(st.name);
    r.quantity.push_back(setup.quantity);
  }
  const int nt = std::max(1, threads);
  std::vector<std::unique_ptr<Eigen::SparseLU<ComplexSparse>>> lu(static_cast<std::size_t>(nt));
  std::mutex mu;
  std::size_t done = 0;
  std::string failure;
  const int k_order = ident::derivative_order(setup.quantity);
  parallel_for(static_cast<std::size_t>(frequency_hz.size()), nt, [&](std::size_t i, int worker) {
    const double w = 2.0 * M_PI * frequency_hz[static_cast<Index>(i)];
    const ComplexSparse A = Kc - (w * w) * Mc + std::complex<double>(0.0, w) * Cc;
    auto& solver = lu[static_cast<std::size_t>(worker)];
    if (!solver) {
      solver = std::make_unique<Eigen::SparseLU<ComplexSparse>>();
      solver->analyzePattern(A);
    }
    solver->factorize(A);
    if (solver->info() != Eigen::Success) {
      std::lock_guard<std::mutex> g(mu);
      failure = "model FRF: K - w^2 M + i w C is singular at " + std::to_string(frequency_hz[static_cast<Index>(i)]) +
                " Hz (an undamped resonance hit exactly? add damping or move the frequency grid)";
      return;
    }
    const Eigen::VectorXcd x = solver->solve(F);
    const std::complex<double> iwk = std::pow(std::complex<double>(0.0, w), k_order);
    for (std::size_t c = 0; c < stations.size(); ++c)
      r.h(static_cast<Index>(i), static_cast<Index>(c)) = iwk * coupling_of(stations[c]).complex_value(x);
    if (progress) {
      std::lock_guard<std::mutex> g(mu);
      progress(++done, static_cast<std::size_t>(frequency_hz.size()));
    }
  });
  if (!failure.empty()) throw SolverError(failure);
  if (!r.h.allFinite()) throw SolverError("model FRF: non-finite response (singular system?)");
  return r;
}

// ---------------------------------------------------------------------------------------------

bool ShakerTest::is_valid(std::string* why) const {
  OptionsCheck c("ShakerTest", why);
  if (!c.require(amplitude_N > 0.0, "amplitude_N", amplitude_N, "amplitude_N > 0 [N]") ||
      !c.require(fs_hz > 0.0, "fs_hz", fs_hz, "fs_hz > 0 [Hz]") ||
      !c.require(substeps >= 0, "substeps", substeps, "substeps >= 0") ||
      !c.require(tail_s >= 0.0, "tail_s", tail_s, "tail_s >= 0 [s]"))
    return false;
  if (kind == Kind::stepped) {
    if (steps.empty()) return c.fail("steps", "[]", "a stepped-sine test needs at least one step");
    double t = 0.0;
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const auto& st = steps[k];
      const std::string at = "steps[" + std::to_string(k) + "]";
      if (!c.require(st.frequency_hz > 0.0, (at + ".frequency_hz").c_str(), st.frequency_hz, "frequency_hz > 0") ||
          !c.require(std::abs(st.t_start_s - t) <= 1e-9, (at + ".t_start_s").c_str(), st.t_start_s,
                     "steps contiguous from t = 0 (this one starts where the previous ends, " + format_number(t, 9) +
                         " s)") ||
          !c.require(st.t_end_s > st.t_start_s, (at + ".t_end_s").c_str(), st.t_end_s, "dwell t_end_s - t_start_s > 0"))
        return false;
      t = st.t_end_s;
    }
  } else if (!c.require(sweep_f_start_hz > 0.0, "sweep_f_start_hz", sweep_f_start_hz, "sweep_f_start_hz > 0") ||
             !c.require(sweep_f_end_hz > sweep_f_start_hz, "sweep_f_end_hz", sweep_f_end_hz,
                        "sweep_f_end_hz > sweep_f_start_hz") ||
             !c.require(sweep_s > 0.0, "sweep_s", sweep_s, "sweep_s > 0 [s]")) {
    return false;
  }
  return c.require(max_frequency_hz() < 0.5 * fs_hz, "fs_hz", fs_hz,
                   "the highest drive frequency " + format_number(max_frequency_hz(), 6) +
                       " Hz below the Nyquist frequency fs_hz/2") &&
         c.require(duration_s() * fs_hz <= 5e7, "fs_hz", fs_hz, "a record of at most 5e7 samples");
}

double ShakerTest::duration_s() const {
  return (kind == Kind::stepped ? (steps.empty() ? 0.0 : steps.back().t_end_s) : sweep_s) + tail_s;
}

double ShakerTest::max_frequency_hz() const {
  if (kind == Kind::swept) return sweep_f_end_hz;
  double f = 0.0;
  for (const auto& s : steps) f = std::max(f, s.frequency_hz);
  return f;
}

ShakerRecord simulate_shaker_test(const model::Structure& s, const ForcedSetup& setup, const ShakerTest& test,
                                  const ProgressSink& progress) {
  std::string why;
  if (!test.is_valid(&why)) throw InputError("shaker test: " + why);
  const auto stations = resolve_stations(s, setup.responses);
  const model::PointCoupling at = model::point_on(s.deck_elements, setup.force_x_m, "deck (exciter position)");
  // Phase at the start of each step: the drive is phase-continuous, as a controller's is.
  std::vector<double> phase0;
  double ph = 0.0;
  for (const auto& st : test.steps) {
    phase0.push_back(ph);
    ph += 2.0 * M_PI * st.frequency_hz * (st.t_end_s - st.t_start_s);
  }
  std::function<double(double)> F;
  if (test.kind == ShakerTest::Kind::stepped) {
    F = [&test, phase0](double t) {
      if (t < 0.0 || t >= test.steps.back().t_end_s) return 0.0;
      const auto it = std::upper_bound(test.steps.begin(), test.steps.end(), t,
                                       [](double v, const ident::SineStep& st) { return v < st.t_end_s; });
      const std::size_t k = static_cast<std::size_t>(it - test.steps.begin());
      return test.amplitude_N * std::sin(phase0[k] + 2.0 * M_PI * it->frequency_hz * (t - it->t_start_s));
    };
  } else {
    const double rate = (test.sweep_f_end_hz - test.sweep_f_start_hz) / test.sweep_s;
    F = [&test, rate](double t) {
      if (t < 0.0 || t > test.sweep_s) return 0.0;
      return test.amplitude_N * std::sin(2.0 * M_PI * (test.sweep_f_start_hz * t + 0.5 * rate * t * t));
    };
  }
  int sub = test.substeps;
  if (sub == 0) sub = std::max(1, static_cast<int>(std::ceil(2.0 * M_PI * test.max_frequency_hz() / (0.03 * test.fs_hz))));
  const ExciterSystem sys(s, at, F);
  // Newmark's average acceleration on every DOF at `sub` steps per sample, behind the one
  // integration face; the stations' chosen quantity kept at every sample.
  solve::IntegrationSettings is;
  is.method = solve::Method::newmark;
  is.dt = 1.0 / (test.fs_hz * sub);
  std::vector<solve::Functional> outputs;
  for (const auto& st : stations) outputs.push_back(functional_of(coupling_of(st)));
  const auto integrator = solve::make_integrator(is, outputs);
  const Index n_samples = static_cast<Index>(std::floor(test.duration_s() * test.fs_hz + 1e-9)) + 1;
  solve::LoadCase lc;
  lc.system = &sys;
  lc.t_end = static_cast<double>(n_samples - 1) / test.fs_hz;
  if (progress) lc.progress = &progress;
  solve::Recording rec;
  rec.disp_history = setup.quantity == ident::FrfQuantity::receptance;
  rec.vel_history = setup.quantity == ident::FrfQuantity::mobility;
  rec.acc_history = !rec.disp_history && !rec.vel_history;
  rec.stride = sub;
  const auto t0 = std::chrono::steady_clock::now();
  const solve::CaseResult cr = integrator->run(lc, rec);
  const Matrix& kept = rec.disp_history ? cr.disp : rec.vel_history ? cr.vel : cr.acc;
  if (kept.rows() < n_samples) throw std::logic_error("shaker: the integrator kept fewer samples than the record has");
  ShakerRecord r;
  r.fs_hz = test.fs_hz;
  r.force.resize(n_samples);
  for (Index j = 0; j < n_samples; ++j) r.force[j] = F(static_cast<double>(j * sub) * is.dt);  // the kernel's own t = k dt
  r.responses = kept.topRows(n_samples);
  for (const auto& st : stations) r.names.push_back(st.name);
  const solve::Summary& summary = cr.summary;
  r.n_steps = summary.n_steps;
  if (test.noise_snr_db >= 0.0) {
    std::mt19937 rng(test.seed);
    auto add = [&](Eigen::Ref<Vector> x) {
      const double rms = std::sqrt(x.squaredNorm() / static_cast<double>(x.size()));
      std::normal_distribution<double> g(0.0, rms * std::pow(10.0, -test.noise_snr_db / 20.0));
      for (Index k = 0; k < x.size(); ++k) x[k] += g(rng);
    };
    add(r.force);
    for (Index c = 0; c < r.responses.cols(); ++c) add(r.responses.col(c));
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

ModelModesAtResponses model_modes_at(const Scenario& sc, const std::vector<std::string>& responses,
                                     const std::vector<std::pair<std::string, double>>& sensors_x, double f_max_hz) {
  const model::Structure s = model::build_structure(sc.bridge, sc.track);
  std::map<std::string, StationSpec> by_name;
  for (const auto& st : sc.stations) by_name[st.name] = st;
  for (const auto& [name, x] : sensors_x) by_name[name] = deck_station_at(s, name, x);
  std::vector<StationSpec> specs;
  for (const auto& n : responses) {
    if (!by_name.count(n)) throw InputError("response '" + n + "' is neither a station of the model nor given by --sensor " + n + "=X");
    specs.push_back(by_name[n]);
  }
  const auto stations = resolve_stations(s, specs);
  const model::Modes md = model::compute_modes_up_to(s, 0, f_max_hz);
  ModelModesAtResponses out;
  out.frequency_hz = md.frequency_hz;
  out.shape.resize(static_cast<Index>(stations.size()), md.frequency_hz.size());
  for (Index j = 0; j < md.frequency_hz.size(); ++j)
    for (std::size_t r = 0; r < stations.size(); ++r) {
      const auto& cp = stations[r].has_deck ? stations[r].deck : stations[r].rail;
      out.shape(static_cast<Index>(r), j) = cp.value(md.shape.col(j));
    }
  return out;
}

}  // namespace viaduct::study

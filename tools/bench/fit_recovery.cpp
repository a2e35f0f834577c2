// Recovery errors and cost of `viaduct fit` on synthetic records with known parameters (issue
// #6): prints markdown tables. Run by scripts/measure/fit_accuracy.sh (docs/fitting-accuracy.md).
//   viaduct_fit_recovery [SOURCE_DIR] [SEEDS]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "../../tests/unit/study/fit_synthetic.hpp"
#include "viaduct/io/fit.hpp"
#include "viaduct/io/scenario.hpp"

using namespace viaduct;
using namespace viaduct::study;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v[v.size() / 2];
}
double worst(const std::vector<double>& v) { return v.empty() ? NAN : *std::max_element(v.begin(), v.end()); }
double stddev(const std::vector<double>& v) {
  double m = 0, s = 0;
  for (double x : v) m += x;
  m /= static_cast<double>(v.size());
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

struct Stats {
  std::vector<double> est, err, rep_std;
  int within2 = 0;
};

void print_rows(const std::string& label, const std::vector<FitParameter>& ps, const std::vector<double>& truth,
                const std::vector<Stats>& st, const std::vector<double>& times, int n_conv, int n) {
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const auto& s = st[i];
    std::printf("| %s | %s | %.4f | %.4f | %.4f | %.4f | %d/%d | %d/%d | %.2f |\n", label.c_str(), ps[i].key.c_str(),
                100 * median(s.err), 100 * worst(s.err), 100 * stddev(s.est) / truth[i], 100 * median(s.rep_std) / truth[i],
                s.within2, n, n_conv, n, median(times));
  }
}

void header() {
  std::printf("| case | parameter | median error [%%] | worst error [%%] | scatter of estimates [%%] | reported std error (median) [%%] | within 2 std errors | converged | fit time (median) [s] |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
}

std::vector<Stats> run_case(const FitProblem& base, const std::vector<double>& truth, int seeds,
                            const std::function<FitRecord(unsigned)>& make_record, const FitOptions& o,
                            std::vector<double>& times, int& n_conv) {
  std::vector<Stats> st(base.params.size());
  n_conv = 0;
  for (int s = 0; s < seeds; ++s) {
    FitProblem p = base;
    p.records = {make_record(static_cast<unsigned>(100 + s))};
    const FitResult r = fit(p, o);
    times.push_back(r.wall_s);
    n_conv += r.status == FitResult::Status::converged;
    for (std::size_t i = 0; i < p.params.size(); ++i) {
      st[i].est.push_back(r.estimate[i]);
      st[i].err.push_back(std::abs(r.estimate[i] / truth[i] - 1));
      st[i].rep_std.push_back(r.std_error[i]);
      st[i].within2 += std::abs(r.estimate[i] - truth[i]) <= 2 * r.std_error[i];
    }
  }
  return st;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string src = argc > 1 ? argv[1] : ".";
  const int seeds = argc > 2 ? std::atoi(argv[2]) : 20;
  std::printf("## Recovery on synthetic records\n\n");
  std::printf("Each case is fitted to `%d` records that differ only in their noise realisation (Gaussian, white,\n", seeds);
  std::printf("added to the unfiltered accelerations). *Scatter* is the standard deviation of the estimates over\n");
  std::printf("the realisations, the error the standard errors should report; *within 2 std errors* counts the\n");
  std::printf("fits whose estimate lies within two reported standard errors of the truth (about 95 %% expected).\n\n");
  header();
  // 1. The small span of the unit tests: EI and damping, time-history objective.
  {
    const std::vector<double> truth = {5.5e9, 0.025};
    FitProblem p;
    p.params = {test::param("bridge.EI", 3e9, 8e9, 5.0e9), test::param("bridge.damping.ratio", 0.005, 0.08, 0.015)};
    p.scenario_at = test::small_scenario;
    FitOptions o;
    o.threads = 2;
    for (double noise : {0.01, 0.03, 0.10}) {
      std::vector<double> times;
      int n_conv = 0;
      const auto st = run_case(p, truth, seeds, [&](unsigned seed) { return test::synthetic_record(truth, noise, seed); }, o, times, n_conv);
      char label[128];
      std::snprintf(label, sizeof label, "12 m span, 3 axles, noise %.0f %% of peak", 100 * noise);
      print_rows(label, p.params, truth, st, times, n_conv, seeds);
    }
  }
  // 2. Old Guadiana, three parameters, two channels, default solver settings (Newmark, 1 ms).
  {
    const io::FlatScenario flat = io::load_flat(src + "/scenarios/old-guadiana-talgo.toml");
    std::vector<FitParameter> ps = {io::fit_parameter(flat, "bridge.EI", 5e9, 1e10, "auto", {}),
                                    io::fit_parameter(flat, "track.pad.k", 2e7, 1e9, "auto", {}),
                                    io::fit_parameter(flat, "bridge.damping.ratio1", 0.01, 0.06, "auto", {})};
    const std::vector<double> truth = {7.8e9, 2e8, 0.025};
    FitProblem p;
    p.params = ps;
    p.scenario_at = io::scenario_builder(flat, ps);
    const Scenario sc = p.scenario_at(truth);
    RunSettings rs = sc.settings;
    rs.filter.enabled = false;
    rs.free_vibration_s = 3.0;
    const PreparedModel pm = prepare_model(sc);
    const RunResult run = simulate(pm, sc.trains[0], *sc.run_speed, rs);
    auto make = [&](unsigned seed) {
      FitRecord rec;
      rec.name = "og";
      rec.fs_hz = 1.0 / rs.dt;
      rec.t0_s = 0.0;
      const auto lead = static_cast<Index>(1.5 * rec.fs_hz);
      const Index n = lead + run.t.size() - static_cast<Index>(1.0 * rec.fs_hz);
      std::mt19937 rng(seed);
      const double rms = std::sqrt(run.stations[0].acc.squaredNorm() / static_cast<double>(run.t.size()));
      std::normal_distribution<double> nd(0.0, 0.05 * rms);
      for (std::size_t s : {std::size_t{0}, std::size_t{2}}) {
        FitChannel ch;
        ch.name = sc.stations[s].name + "_acc_mps2";
        ch.station = sc.stations[s].name;
        ch.samples = Vector::Zero(n);
        for (Index j = lead; j < n; ++j) ch.samples[j] = run.stations[s].acc[j - lead];
        for (Index j = 0; j < n; ++j) ch.samples[j] += nd(rng);
        rec.channels.push_back(ch);
      }
      return rec;
    };
    FitOptions o;
    o.threads = 2;
    std::vector<double> times;
    int n_conv = 0;
    const int og_seeds = std::max(1, seeds / 4);
    const auto st = run_case(p, truth, og_seeds, make, o, times, n_conv);
    print_rows("Old Guadiana, Talgo at 154.8 km/h, 2 channels, noise 5 % of RMS", p.params, truth, st, times, n_conv, og_seeds);
  }
  return 0;
}

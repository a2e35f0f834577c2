// The Python package's model updating: viaduct fit's request (parameters with bounds, records,
// channel maps, identified modes, weights) through io::fit_setup and study::fit, the result as
// estimates, standard errors and flags.
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <future>
#include <mutex>
#include <optional>

#include "viaduct/io/fit.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/fit.hpp"
#include "viaduct_py.hpp"

namespace viaduct_py {

namespace {

namespace io = viaduct::io;
namespace study = viaduct::study;

py::dict result_dict(const study::FitProblem& problem, const study::FitResult& r) {
  py::dict d;
  d["status"] = study::to_string(r.status);
  d["message"] = r.message;
  std::vector<std::string> key, unit;
  for (const auto& p : problem.params) {
    key.push_back(p.key);
    unit.push_back(p.unit);
  }
  py::dict params;
  params["key"] = key;
  params["unit"] = unit;
  params["initial"] = r.initial;
  params["estimate"] = r.estimate;
  params["std_error"] = r.std_error;
  params["sensitivity"] = r.sensitivity;
  params["at_bound"] = r.at_bound;
  params["determined"] = r.determined;
  d["params"] = params;
  d["correlation"] = matrix_to_numpy(Matrix(r.correlation));
  d["warnings"] = r.warnings;
  d["shift_s"] = r.shift_s;
  d["cost_initial"] = r.cost_initial;
  d["cost_final"] = r.cost_final;
  d["iterations"] = r.iterations;
  d["simulations"] = r.simulations;
  d["wall_s"] = r.wall_s;
  py::list pairs;
  for (const auto& m : r.modal_pairs) {
    py::dict p;
    p["frequency_hz"] = m.frequency_hz;
    p["model_before_hz"] = m.model_before_hz;
    p["model_after_hz"] = m.model_after_hz;
    p["mac_before"] = m.mac_before;
    p["mac_after"] = m.mac_after;
    p["damping_ratio"] = m.damping_ratio;
    p["model_damping_before"] = m.model_damping_before;
    p["model_damping_after"] = m.model_damping_after;
    pairs.append(p);
  }
  d["modal_pairs"] = pairs;
  return d;
}

py::dict fit(const io::FlatScenario& flat, const io::FitRequest& request, std::optional<std::string> out, const py::object& progress) {
  auto [problem, options] = io::fit_setup(flat, request);
  // Iterations are reported from the waiting thread, with the GIL: the solver's callback only
  // counts them here.
  std::atomic<std::size_t> done{0}, total{0};
  std::atomic<bool> cancel{false};
  std::mutex last_mutex;
  study::FitTracePoint last;
  options.progress = [&](const study::FitTracePoint& tp) {
    std::lock_guard<std::mutex> lock(last_mutex);
    last = tp;
    ++done;
  };
  py::object report = py::none();
  if (!progress.is_none())
    report = py::cpp_function([&, progress](std::size_t, std::size_t) {
      study::FitTracePoint tp;
      {
        std::lock_guard<std::mutex> lock(last_mutex);
        tp = last;
      }
      progress(tp.start, tp.stage, tp.iteration, tp.cost, tp.values);
    });
  const study::FitResult r = interruptible([&] { return study::fit(problem, options); }, report, done, total, cancel);
  if (out) io::write_fit_outputs(*out, flat.path, flat, problem, options, r);
  return result_dict(problem, r);
}

}  // namespace

void bind_fit(py::module_& m) {
  m.def(
      "fit",
      [](const io::FlatScenario& flat, const std::vector<std::string>& params, const std::vector<std::string>& records,
         const std::vector<std::string>& maps, const std::vector<double>& speeds_kmh, const std::string& train,
         std::optional<std::string> modes, std::optional<std::string> modes_method, const std::vector<std::string>& weights,
         std::optional<int> starts, std::optional<int> max_iterations, std::optional<double> max_time_s, bool spectral_start,
         int threads, std::optional<std::string> out, const py::object& progress) {
        io::FitRequest q;
        q.params = params;
        q.records = records;
        q.maps = maps;
        q.speeds_kmh = speeds_kmh;
        q.train = train;
        q.modes = modes;
        q.modes_method = modes_method;
        q.weights = weights;
        q.starts = starts;
        q.max_iterations = max_iterations;
        q.max_time_s = max_time_s;
        q.no_spectral_start = !spectral_start;
        q.threads = threads_of(threads);
        return fit(flat, q, out, progress);
      },
      py::arg("flat"), py::arg("params"), py::arg("records"), py::arg("maps"), py::arg("speeds_kmh"), py::arg("train"),
      py::arg("modes"), py::arg("modes_method"), py::arg("weights"), py::arg("starts"), py::arg("max_iterations"),
      py::arg("max_time_s"), py::arg("spectral_start"), py::arg("threads"), py::arg("out"), py::arg("progress"));
}

}  // namespace viaduct_py

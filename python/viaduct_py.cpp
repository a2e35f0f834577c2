// The Python package's core (_viaduct): the library's own functions on numpy arrays. The
// package (python/viaduct/__init__.py) wraps it in the documented names; docs/python.md.
//
// No copies between numpy and the core where the core can read in place: results are Eigen
// vectors moved to the heap and handed to numpy with a capsule that frees them; a float64,
// contiguous array goes to the filter as an Eigen::Map. Long calls run on a worker thread while
// the calling thread, without the GIL, wakes every 0.1 s to report progress and to see Ctrl-C
// (PyErr_CheckSignals): a sweep then skips the cases not yet started and KeyboardInterrupt is
// raised.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <optional>
#include <chrono>
#include <future>
#include <thread>

#include "viaduct/core/error.hpp"
#include "viaduct/core/simd.hpp"
#include "viaduct_py.hpp"
#include "viaduct/io/assessment.hpp"
#include "viaduct/io/report_html.hpp"
#include "viaduct/io/output_dir.hpp"
#include "viaduct/io/passages.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/io/sampled.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/io/traffic_mix.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/rainflow.hpp"
#include "viaduct/study/fatigue.hpp"
#include "viaduct/signal/spectrum.hpp"
#include "viaduct/study/comparison.hpp"
#include "viaduct/study/assessment.hpp"
#include "viaduct/study/sweep.hpp"

namespace py = pybind11;

namespace viaduct_py {

using viaduct::Index;
using viaduct::InputError;
using viaduct::Vector;

// A scenario value as Python sees it.
py::object to_python(const viaduct::io::Value& v) {
  using viaduct::io::ValueType;
  switch (v.type) {
    case ValueType::boolean: return py::bool_(v.b);
    case ValueType::integer: return py::int_(static_cast<long long>(v.x));
    case ValueType::number: return py::float_(v.x);
    case ValueType::string: return py::str(v.s);
    case ValueType::number_list: return py::cast(v.xs);
    case ValueType::string_list: return py::cast(v.ss);
    default: return py::float_(v.x);
  }
}

// A table's columns by name: lists of str, float64 arrays, bool arrays.
py::dict columns_dict(std::vector<viaduct::io::TableColumn>&& columns) {
  using Kind = viaduct::io::TableColumn::Kind;
  py::dict d;
  for (auto& c : columns) {
    if (c.kind == Kind::text) {
      d[py::str(c.name)] = py::cast(c.cells);
    } else if (c.kind == Kind::number) {
      d[py::str(c.name)] = to_numpy(std::move(c.values));
    } else {
      py::array_t<bool> flags(static_cast<py::ssize_t>(c.flags.size()));
      for (std::size_t i = 0; i < c.flags.size(); ++i) flags.mutable_at(static_cast<py::ssize_t>(i)) = c.flags[i] != 0;
      d[py::str(c.name)] = flags;
    }
  }
  return d;
}

// One train at one speed: history.csv's columns (names, arrays) and what ran.
py::tuple run(const viaduct::io::FlatScenario& flat, std::optional<double> speed_kmh, std::optional<std::string> train,
              const py::object& progress) {
  namespace study = viaduct::study;
  study::Scenario sc = viaduct::io::to_scenario(flat);
  const double speed = study::passage_speed(sc, speed_kmh, "speed_kmh");
  const viaduct::load::Train t = study::passage_train(sc, train);
  CallState call(1);
  auto r = std::make_shared<study::RunResult>(interruptible(
      [&] {
        const study::PreparedModel pm = study::prepare_model(sc, /*rail_outputs=*/true, /*with_load_effects=*/true);
        study::RunResult out = study::simulate(pm, t, speed, sc.settings);
        call.done = 1;
        return out;
      },
      progress, call));
  // The columns point into the result: numpy views kept alive by one capsule holding it.
  py::capsule owner(new std::shared_ptr<study::RunResult>(r),
                    [](void* q) { delete static_cast<std::shared_ptr<study::RunResult>*>(q); });
  py::list names, columns;
  for (const auto& [name, col] : viaduct::io::history_columns(*r)) {
    names.append(name);
    columns.append(py::array_t<double>({col->size()}, {static_cast<py::ssize_t>(sizeof(double))}, col->data(), owner));
  }
  py::dict info;
  const study::VehicleHistory& v = r->vehicles;
  if (!v.empty()) {  // vehicles.csv's columns: each axle's contact force, each car body's acceleration
    py::dict vehicles;
    vehicles["t_s"] = py::array_t<double>({r->t.size()}, {static_cast<py::ssize_t>(sizeof(double))}, r->t.data(), owner);
    for (Index k = 0; k < v.contact_force.cols(); ++k)
      vehicles[py::str("a" + std::to_string(k + 1) + "_contact_N")] = to_numpy(Vector(v.contact_force.col(k)));
    for (std::size_t b = 0; b < v.body_names.size(); ++b)
      vehicles[py::str(v.body_names[b] + "_acc_mps2")] = to_numpy(Vector(v.body_acc.col(static_cast<Index>(b))));
    info["vehicles"] = vehicles;
  }
  info["train"] = t.name;
  info["speed_kmh"] = speed * 3.6;
  info["method"] = viaduct::solve::method_name(sc.settings.method);
  info["n_steps"] = r->summary.n_steps;
  info["n_modes"] = r->n_modes;
  return py::make_tuple(names, columns, info);
}

// The sweep's envelope (envelope.csv's columns), failures and governing cases.
py::tuple sweep(const viaduct::io::FlatScenario& flat, int threads, bool load_effects, const py::object& progress) {
  namespace study = viaduct::study;
  if (viaduct::io::is_sampled(flat))
    throw InputError(flat.at("sweep.mode").where, "a sampled study (sweep.mode = \"sample\"): run it with viaduct.sampled_sweep(scenario, out)");
  const std::vector<study::Variant> variants = viaduct::io::sweep_variants(flat, /*isolate_failures=*/true);
  if (variants.front().scenario.sweep_speeds.empty())
    throw InputError("no speeds: give sweep.speeds_kmh, sweep.speed_min/max/step_kmh or sweep.speed_min/max_mps with n_speeds");
  CallState call(study::count_cases(variants));
  study::SweepOptions so;
  so.threads = threads_of(threads);
  so.load_effects = load_effects;
  so.cancel = &call.cancel;
  so.progress = call.sink();
  const study::SweepResult r = interruptible([&] { return study::run_sweep(variants, so); }, progress, call);
  if (r.summary.cancelled) {  // cut without a Ctrl-C reaching this thread: still never a partial table
    PyErr_SetString(PyExc_KeyboardInterrupt, "the sweep was cancelled: its cases are incomplete");
    throw py::error_already_set();
  }
  py::dict tables;
  tables["envelope"] = columns_dict(viaduct::io::envelope_columns(r.rows, variants));
  if (load_effects) tables["load_effects"] = columns_dict(viaduct::io::quantity_columns(r.quantities, variants));
  if (!r.vehicles.empty()) tables["vehicles"] = columns_dict(viaduct::io::vehicle_envelope_columns(r.vehicles, variants));
  py::list failures, governing;
  for (const auto& f : r.failures) failures.append(py::make_tuple(f.variant, f.train, f.speed * 3.6, f.message));
  for (const auto& g : study::governing(r.rows))
    governing.append(py::make_tuple(g.station, g.acc.value, g.acc.variant, g.acc.train, g.acc.speed * 3.6, g.disp.value,
                                    g.disp.variant, g.disp.train, g.disp.speed * 3.6));
  return py::make_tuple(tables, failures, governing);
}

// The dynamic check (viaduct assess): the plan from the scenario's [assess] keys, the runs, the
// checks; with `out` the CLI's tables and report.md (without figures) there too.
py::tuple assess(const viaduct::io::FlatScenario& flat_in, int threads, const py::object& progress,
                 const std::optional<std::string>& out) {
  namespace study = viaduct::study;
  namespace io = viaduct::io;
  io::FlatScenario flat = flat_in;
  const study::AssessPlan plan = io::plan_assessment(flat, flat.path, threads_of(threads));
  CallState call(study::count_cases(plan.variants));
  study::AssessOptions ao;
  ao.threads = threads_of(threads);
  ao.cancel = &call.cancel;
  ao.progress = call.sink();
  const study::AssessResult r = interruptible([&] { return study::run_assessment(plan, ao); }, progress, call);
  if (r.sweep.summary.cancelled) {
    PyErr_SetString(PyExc_KeyboardInterrupt, "the assessment was cancelled: its cases are incomplete");
    throw py::error_already_set();
  }
  const std::string report = io::assessment_report(r, flat, "viaduct.assess (Python)", false);
  if (out) {
    io::begin_outputs(*out);
    io::write_assessment_tables(*out, r, ao.threads);
    io::write_text_file(*out + "/report.md", report);
    io::write_text_file(*out + "/report.html", io::report_html(report, r.nominal().title, *out));
  }
  py::dict tables;
  tables["envelope"] = columns_dict(io::envelope_columns(r.sweep.rows, r.plan.variants));
  tables["load_effects"] = columns_dict(io::quantity_columns(r.sweep.quantities, r.plan.variants));
  tables["phi_dyn"] = columns_dict(io::assessment_increment_columns(r.increments));
  py::dict info;
  info["f1_hz"] = r.plan.f1;
  info["f3_hz"] = r.plan.f3;
  info["cutoff_hz"] = r.plan.f_cut;
  info["damping_ratio"] = r.plan.zeta;
  info["n_cases"] = r.sweep.summary.n_cases;
  info["n_failed"] = r.sweep.summary.n_failed;
  info["notes"] = r.plan.notes;
  info["warnings"] = r.plan.warnings;
  info["report"] = report;
  return py::make_tuple(columns_dict(io::assessment_check_columns(r.checks)), tables, info);
}

// A sampled study (viaduct sweep on sweep.mode = "sample"): io::run_sampled, the CLI's function,
// into `out` (its files: the statistics are streamed from the peaks on disk). Returns what ran.
py::dict sampled_sweep(const viaduct::io::FlatScenario& flat, const std::string& out, int threads, bool resume,
                       const py::object& progress) {
  namespace io = viaduct::io;
  if (!io::is_sampled(flat)) throw InputError("sampled_sweep: the scenario is not a sampled study (sweep.mode = \"sample\"); use sweep()");
  io::SampledRunRequest q;
  q.out = out;
  q.threads = threads_of(threads);
  q.resume = resume;
  CallState call;
  q.progress = call.sink();
  const io::SampledRunOutcome r = interruptible([&] { return io::run_sampled(flat, q); }, progress, call);
  py::dict info;
  info["n_samples_total"] = r.study.n_total();
  info["n_samples_run"] = r.summary.n_samples;
  info["n_cases_run"] = r.summary.n_cases;
  info["n_failed_run"] = r.summary.n_failed;
  info["sensitivity"] = r.study.spec.sensitivity;
  info["fingerprint"] = r.study.fingerprint;
  info["warnings"] = r.warnings;
  return info;
}

// A traffic mix over the scenario's model (viaduct fatigue SCENARIO --mix): the library's
// functions the CLI calls, its two tables as columns, what the total says.
py::tuple fatigue_mix(const viaduct::io::FlatScenario& flat, const std::string& mix_path, const std::string& channel,
                      std::optional<double> detail, std::optional<double> delta_c_mpa, double m1, double m2,
                      std::optional<double> section_modulus_m3, double youngs_modulus_pa, double gamma_ff, double gamma_mf,
                      const std::string& method, double hysteresis_mpa, double range_bin_mpa, double mean_bin_mpa, int threads,
                      const py::object& progress) {
  namespace study = viaduct::study;
  namespace io = viaduct::io;
  study::FatigueCount f;
  f.curve = study::sn_curve(detail, delta_c_mpa, m1, m2);
  f.gamma_ff = gamma_ff;
  f.gamma_mf = gamma_mf;
  f.method = viaduct::signal::rainflow_method(method, "method");
  f.hysteresis_mpa = hysteresis_mpa;
  f.range_bin_mpa = range_bin_mpa;
  f.mean_bin_mpa = mean_bin_mpa;
  if (!(range_bin_mpa > 0.0) || !(mean_bin_mpa > 0.0) || !(hysteresis_mpa >= 0.0))
    throw InputError("fatigue_mix: range_bin_mpa and mean_bin_mpa must be > 0, hysteresis_mpa >= 0");
  const study::Scenario sc = io::to_scenario(flat);
  const study::TrafficMix mix = io::read_traffic_mix(mix_path);
  CallState call(mix.trains.size());
  const study::MixDamage d = interruptible(
      [&] {
        const study::PreparedModel pm = study::prepare_model(sc, true, /*with_load_effects=*/true);
        const std::size_t effect = study::fatigue_effect(pm, channel);
        const std::string& name = pm.effects[effect].name;
        const double to_pa = study::stress_per_unit(name, name.substr(name.rfind('_') + 1), youngs_modulus_pa, section_modulus_m3);
        return study::traffic_damage(pm, sc.settings, effect, to_pa, mix, f, threads_of(threads), call.sink());
      },
      progress, call);
  py::dict info;
  info["title"] = mix.title;
  info["curve"] = f.curve.name;
  info["damage_per_year"] = d.per_year;
  info["years_to_d1"] = d.years_to_d1();
  info["n_failed"] = d.n_failed;
  return py::make_tuple(columns_dict(io::fatigue_mix_damage_columns(d, f)), columns_dict(io::fatigue_mix_cycle_columns(d, f)), info);
}

// Recorded passages over the model's envelope (viaduct passages): io::run_passages, the CLI's
// function; with `out` its four tables there too (no manifest).
py::tuple passages(const viaduct::io::FlatScenario& flat, const std::vector<std::string>& records, const std::vector<std::string>& maps,
                   std::optional<std::string> train, std::optional<double> v_min_kmh, std::optional<double> v_max_kmh,
                   double speed_band, double noise_band, const std::string& zero, const std::string& time_column,
                   std::optional<double> fs_hz, int header_line, int skip_lines, int threads, const py::object& progress,
                   const std::optional<std::string>& out) {
  namespace io = viaduct::io;
  io::PassagesRequest q;
  q.records = records;
  q.maps = maps;
  q.train = std::move(train);
  q.v_min_kmh = v_min_kmh;
  q.v_max_kmh = v_max_kmh;
  q.speed_band = speed_band;
  q.noise_band = noise_band;
  q.zero = zero;
  q.read.time_column = time_column;
  q.read.fs_hz = fs_hz;
  if (header_line < 0 || skip_lines < 0) throw InputError("passages: header_line and skip_lines must be >= 0");
  q.read.header_line = header_line;
  q.read.skip_lines = skip_lines;
  q.threads = threads_of(threads);
  // What reading repaired and what was cut are warnings here (the CLI prints them as they come).
  std::vector<std::string> read_warnings;
  std::mutex read_mutex;
  q.on_read = [&](const std::string& path, const io::ImportReport& rep) {
    const auto lines = io::describe(rep);
    std::lock_guard<std::mutex> lock(read_mutex);
    for (std::size_t i = lines.size() - rep.repairs.size(); i < lines.size(); ++i) read_warnings.push_back(path + ": " + lines[i]);
  };
  q.on_cut = [&](const std::string& note) {
    std::lock_guard<std::mutex> lock(read_mutex);
    read_warnings.push_back(note);
  };
  CallState call;
  q.progress = call.sink();
  const io::PassagesOutcome r = interruptible([&] { return io::run_passages(flat, q); }, progress, call);
  if (out) {
    io::begin_outputs(*out);
    io::write_passages_tables(*out, r);
  }
  py::dict tables;
  tables["passages_summary"] = columns_dict(io::passage_summary_columns(r));
  tables["model_envelope"] = columns_dict(io::passage_envelope_columns(r));
  tables["failures"] = columns_dict(io::passage_failure_columns(r));
  py::dict info;
  read_warnings.insert(read_warnings.end(), r.warnings.begin(), r.warnings.end());
  info["warnings"] = read_warnings;
  info["n_passages"] = r.study.passages.size();
  info["n_failed"] = r.n_failed;
  return py::make_tuple(columns_dict(io::passage_columns(r)), tables, info);
}

viaduct::signal::Cheby1Spec cheby_of(double low_hz, double high_hz, int order, double ripple_db, const std::string& band) {
  viaduct::signal::Cheby1Spec spec;
  spec.order = order;
  spec.ripple_db = ripple_db;
  spec.low_hz = low_hz;
  spec.high_hz = high_hz;
  if (band == "bandpass") spec.band = viaduct::signal::BandType::bandpass;
  else if (band == "lowpass") spec.band = viaduct::signal::BandType::lowpass;
  else if (band == "highpass") spec.band = viaduct::signal::BandType::highpass;
  else throw InputError("band must be bandpass, lowpass or highpass, got '" + band + "'");
  return spec;
}

// A record channel against a model quantity (viaduct compare's metrics and overlays).
py::dict compare(const py::handle& record, double fs_record, const py::handle& model, double fs_model, double t0_record,
                 const viaduct::signal::Cheby1Spec& spec, bool filter, double max_shift_s, double spectrum_max_hz) {
  namespace study = viaduct::study;
  py::array_t<double, py::array::c_style | py::array::forcecast> keep_r, keep_m;
  const Vector r = view(record, keep_r, "compare: record"), m = view(model, keep_m, "compare: model");
  study::ComparisonOptions o;
  o.filter.enabled = filter;
  o.filter.cheby = spec;
  o.max_shift_s = max_shift_s;
  o.spectrum_max_hz = spectrum_max_hz;
  study::ChannelComparison c;
  {
    py::gil_scoped_release nogil;
    c = study::compare_channel(r, fs_record, t0_record, m, fs_model, o);
  }
  py::dict d;
  d["shift_s"] = c.shift_s;
  d["peak_record"] = c.peak_record;
  d["peak_model"] = c.peak_model;
  d["peak_ratio"] = c.peak_ratio;
  d["rms_ratio"] = c.rms_ratio;
  d["correlation"] = c.correlation;
  d["f_peak_record_hz"] = c.f_peak_record_hz;
  d["f_peak_model_hz"] = c.f_peak_model_hz;
  d["spectral_correlation"] = c.spectral_correlation;
  // a unit's factor between record and model with the same shape: the warning viaduct compare prints
  d["unit_warning"] = study::unit_slip_warning(c.peak_ratio, c.rms_ratio, c.correlation, "record");
  d["t"] = to_numpy(std::move(c.t));
  d["record"] = to_numpy(std::move(c.record));
  d["model"] = to_numpy(std::move(c.model));
  d["frequency_hz"] = to_numpy(std::move(c.frequency_hz));
  d["record_amplitude"] = to_numpy(std::move(c.record_amplitude));
  d["model_amplitude"] = to_numpy(std::move(c.model_amplitude));
  return d;
}


// Rainflow counting and Miner damage (viaduct fatigue's functions; docs/fatigue.md).
void bind_fatigue(py::module_& m) {
  namespace signal = viaduct::signal;
  namespace study = viaduct::study;
  m.def(
      "rainflow",
      [](const py::handle& x, const std::string& method, double hysteresis) {
        py::array_t<double, py::array::c_style | py::array::forcecast> keep;
        const Eigen::Map<const Vector> in = view(x, keep, "rainflow");
        std::vector<signal::Cycle> cs;
        {
          py::gil_scoped_release nogil;
          cs = signal::rainflow(in, signal::rainflow_method(method), hysteresis);
        }
        Vector range(static_cast<Index>(cs.size())), mean(range.size()), count(range.size());
        for (std::size_t i = 0; i < cs.size(); ++i) {
          const auto k = static_cast<Index>(i);
          range[k] = cs[i].range, mean[k] = cs[i].mean, count[k] = cs[i].count;
        }
        return py::make_tuple(to_numpy(std::move(range)), to_numpy(std::move(mean)), to_numpy(std::move(count)));
      },
      py::arg("x"), py::arg("method") = "three-point", py::arg("hysteresis") = 0.0);
  m.def(
      "miner_damage",
      [](const py::handle& ranges, const py::handle& counts, double detail, double delta_c_mpa, double m1, double m2, double to_pa,
         double gamma_ff, double gamma_mf) {
        py::array_t<double, py::array::c_style | py::array::forcecast> keep_r, keep_c;
        const Eigen::Map<const Vector> r = view(ranges, keep_r, "miner_damage");
        const Eigen::Map<const Vector> c = view(counts, keep_c, "miner_damage");
        if (r.size() != c.size()) throw InputError("miner_damage: ranges and counts differ in length");
        if ((detail > 0) == (delta_c_mpa > 0)) throw InputError("miner_damage: give exactly one of detail or delta_c_mpa");
        study::MinerSum sum(detail > 0 ? study::SnCurve::en1993_1_9(detail) : study::SnCurve::two_slopes(delta_c_mpa * 1e6, m1, m2), to_pa,
                            gamma_ff, gamma_mf);
        for (Index i = 0; i < r.size(); ++i) {
          if (!(r[i] >= 0.0) || !(c[i] >= 0.0)) throw InputError("miner_damage: range and count " + std::to_string(i) + " must be >= 0");
          sum.add(signal::Cycle{r[i], 0.0, c[i]});
        }
        return sum.damage;
      },
      py::arg("ranges"), py::arg("counts"), py::arg("detail") = 0.0, py::arg("delta_c_mpa") = 0.0, py::arg("m1") = 3.0,
      py::arg("m2") = 5.0, py::arg("to_pa") = 1.0, py::arg("gamma_ff") = 1.0, py::arg("gamma_mf") = 1.0);
}

void bind(py::module_& m) {
  namespace io = viaduct::io;
  namespace signal = viaduct::signal;
  namespace study = viaduct::study;
  py::class_<io::FlatScenario>(m, "FlatScenario")
      .def_readonly("path", &io::FlatScenario::path)
      .def("get", [](const io::FlatScenario& f, const std::string& key) { return to_python(f.at(key)); })
      .def("has", &io::FlatScenario::has)
      .def("keys", [](const io::FlatScenario& f) {
        std::vector<std::string> k;
        for (const auto& kv : f.values) k.push_back(kv.first);
        return k;
      })
      .def("where", [](const io::FlatScenario& f, const std::string& key) {
        const auto& w = f.at(key).where;
        return py::make_tuple(w.file, w.line);
      })
      .def("resolved_toml", [](const io::FlatScenario& f) { return io::resolved_toml(f); })
      .def("describe", [](const io::FlatScenario& f) { return io::format_resolved(f); });
  m.def(
      "load_flat",
      [](const std::string& path, const std::vector<std::string>& overrides) {
        io::FlatScenario f = io::load_flat(path, overrides);
        (void)io::to_scenario(f);  // the cross-key rules, as viaduct check
        return f;
      },
      py::arg("path"), py::arg("overrides") = std::vector<std::string>{});
  m.def("run", &run, py::arg("flat"), py::arg("speed_kmh") = py::none(), py::arg("train") = py::none(),
        py::arg("progress") = py::none());
  m.def("sweep", &sweep, py::arg("flat"), py::arg("threads") = 1, py::arg("load_effects") = false,
        py::arg("progress") = py::none());
  m.def("assess", &assess, py::arg("flat"), py::arg("threads") = 1, py::arg("progress") = py::none(),
        py::arg("out") = py::none());
  m.def("sampled_sweep", &sampled_sweep, py::arg("flat"), py::arg("out"), py::arg("threads"), py::arg("resume"),
        py::arg("progress"));
  m.def("fatigue_mix", &fatigue_mix, py::arg("flat"), py::arg("mix"), py::arg("channel"), py::arg("detail"), py::arg("delta_c_mpa"),
        py::arg("m1"), py::arg("m2"), py::arg("section_modulus_m3"), py::arg("youngs_modulus_pa"), py::arg("gamma_ff"),
        py::arg("gamma_mf"), py::arg("method"), py::arg("hysteresis_mpa"), py::arg("range_bin_mpa"), py::arg("mean_bin_mpa"),
        py::arg("threads"), py::arg("progress") = py::none());
  m.def("passages", &passages, py::arg("flat"), py::arg("records"), py::arg("maps"), py::arg("train"), py::arg("v_min_kmh"),
        py::arg("v_max_kmh"), py::arg("speed_band"), py::arg("noise_band"), py::arg("zero"), py::arg("time_column"),
        py::arg("fs_hz"), py::arg("header_line"), py::arg("skip_lines"), py::arg("threads"), py::arg("progress"), py::arg("out"));
  m.def(
      "read_record",
      [](const std::string& path, const std::string& time_column, std::optional<double> fs_hz, int header_line, int skip_lines) {
        io::ReadOptions o;
        o.time_column = time_column;
        o.fs_hz = fs_hz;
        if (header_line < 0 || skip_lines < 0) throw InputError("read_record: header_line and skip_lines must be >= 0");
        o.header_line = header_line;
        o.skip_lines = skip_lines;
        auto r = std::make_shared<io::Record>(io::read_record(path, o));
        // The samples stay where the reader put them (column-major): a Fortran-ordered view.
        py::capsule owner(new std::shared_ptr<io::Record>(r), [](void* q) { delete static_cast<std::shared_ptr<io::Record>*>(q); });
        const auto rows = static_cast<py::ssize_t>(r->data.rows()), cols = static_cast<py::ssize_t>(r->data.cols());
        const auto s = static_cast<py::ssize_t>(sizeof(double));
        py::array_t<double> data({rows, cols}, {s, s * rows}, r->data.data(), owner);
        return py::make_tuple(data, r->channels, r->units, r->fs_hz, r->t0_s);
      },
      py::arg("path"), py::arg("time_column") = "", py::arg("fs_hz") = py::none(), py::arg("header_line") = 0, py::arg("skip_lines") = 0);
  m.def(
      "filter",
      [](const py::handle& x, double fs_hz, double low_hz, double high_hz, int order, double ripple_db, const std::string& band) {
        const signal::Cheby1Spec spec = cheby_of(low_hz, high_hz, order, ripple_db, band);
        py::array_t<double, py::array::c_style | py::array::forcecast> keep;
        const Eigen::Map<const Vector> in = view(x, keep, "filter");
        if (!in.allFinite())  // as every other function: never NaN out for NaN in
          throw InputError("filter: x holds non-finite samples (NaN or infinity); fill or cut them first");
        const signal::Sos sos = signal::cheby1(spec, fs_hz);
        Vector y;
        {
          py::gil_scoped_release nogil;
          y = signal::sosfiltfilt(sos, in);
        }
        return to_numpy(std::move(y));
      },
      py::arg("x"), py::arg("fs_hz"), py::arg("low_hz"), py::arg("high_hz"), py::arg("order") = 3, py::arg("ripple_db") = 0.5,
      py::arg("band") = "bandpass");
  m.def(
      "spectrum",
      [](const py::handle& x, double fs_hz, const std::string& window) {
        py::array_t<double, py::array::c_style | py::array::forcecast> keep;
        const Vector in = view(x, keep, "spectrum");
        signal::AmplitudeSpectrum a = signal::amplitude_spectrum(in, fs_hz, signal::window_of(window));
        return py::make_tuple(to_numpy(std::move(a.frequency_hz)), to_numpy(std::move(a.amplitude)));
      },
      py::arg("x"), py::arg("fs_hz"), py::arg("window") = "hann");
  m.def(
      "welch",
      [](const py::handle& x, double fs_hz, Index nperseg, Index noverlap, const std::string& window, const std::string& detrend) {
        py::array_t<double, py::array::c_style | py::array::forcecast> keep;
        const Vector in = view(x, keep, "welch");
        signal::WelchOptions o;
        o.nperseg = nperseg;
        o.noverlap = noverlap;
        o.window = signal::window_of(window);
        o.detrend = signal::detrend_of(detrend);
        signal::Psd p = signal::welch(in, fs_hz, o);
        return py::make_tuple(to_numpy(std::move(p.frequency_hz)), to_numpy(std::move(p.density)));
      },
      py::arg("x"), py::arg("fs_hz"), py::arg("nperseg") = 256, py::arg("noverlap") = -1, py::arg("window") = "hann",
      py::arg("detrend") = "constant");
  m.def(
      "compare",
      [](const py::handle& record, double fs_record, const py::handle& model, double fs_model, double t0_record, double low_hz,
         double high_hz, int order, double ripple_db, const std::string& band, bool filter, double max_shift_s,
         double spectrum_max_hz) {
        return compare(record, fs_record, model, fs_model, t0_record, cheby_of(low_hz, high_hz, order, ripple_db, band), filter,
                       max_shift_s, spectrum_max_hz);
      },
      py::arg("record"), py::arg("fs_record"), py::arg("model"), py::arg("fs_model"), py::arg("t0_record") = 0.0,
      py::arg("low_hz") = 1.0, py::arg("high_hz") = 30.0, py::arg("order") = 3, py::arg("ripple_db") = 0.5,
      py::arg("band") = "bandpass", py::arg("filter") = true, py::arg("max_shift_s") = 60.0, py::arg("spectrum_max_hz") = 0.0);
  bind_fatigue(m);
  m.def("version", [] { return viaduct::io::version(); });
}

}  // namespace viaduct_py

PYBIND11_MODULE(_viaduct, m) {
  m.doc() = "viaduct's C++ core (use the viaduct package)";
  // The errors of the CLI, with its text (file, line, key): InputError is a ValueError,
  // SolverError a RuntimeError.
  static py::exception<viaduct::InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<viaduct::SolverError> solver_error(m, "SolverError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const viaduct::InputError& e) {
      input_error(e.what());
    } catch (const viaduct::SolverError& e) {
      solver_error(e.what());
    }
  });
  viaduct_py::bind(m);
  viaduct_py::bind_ident(m);
  viaduct_py::bind_fit(m);
  // A wrong VIADUCT_SIMD fails the import (an ImportError with its message), as it stops the CLI: a sweep
  // would otherwise retry its blocks on the general path and say nothing.
  viaduct::simd_level();
}

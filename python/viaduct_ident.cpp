// The Python package's identification functions: FRFs of forced-vibration tests, modal fits and
// free decays on arrays, with the CLI's functions (viaduct frf, modal-fit, decay).
#include <pybind11/complex.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <optional>

#include "viaduct/ident/decay.hpp"
#include "viaduct/ident/frf_estimate.hpp"
#include "viaduct/ident/modal_fit.hpp"
#include "viaduct/ident/oma.hpp"
#include "viaduct/io/frf.hpp"
#include "viaduct/signal/peaks.hpp"
#include "viaduct/study/speed.hpp"
#include "viaduct_py.hpp"

namespace viaduct_py {

namespace ident = viaduct::ident;
namespace io = viaduct::io;

namespace {

// Samples × channels as a matrix (a 1-D array is one channel).
Matrix matrix_of(const py::handle& x, const char* what) {
  auto a = py::array_t<double, py::array::f_style | py::array::forcecast>::ensure(x);
  if (!a || (a.ndim() != 1 && a.ndim() != 2))
    throw InputError(std::string(what) + ": expected a 1-D or 2-D array of numbers (samples x channels)");
  const Index rows = a.shape(0), cols = a.ndim() == 2 ? a.shape(1) : 1;
  return Eigen::Map<const Matrix>(a.data(), rows, cols);
}

const char* quantity_name(ident::FrfQuantity q) {
  return q == ident::FrfQuantity::receptance ? "receptance" : q == ident::FrfQuantity::mobility ? "mobility" : "accelerance";
}

// An FRF as a dict: frequency_hz, h (complex, frequencies x responses), coherence (or None),
// responses, units, quantities, force_unit.
py::dict frf_dict(const ident::Frf& f) {
  py::dict d;
  d["frequency_hz"] = to_numpy(Vector(f.frequency_hz));
  d["h"] = matrix_to_numpy(ident::ComplexMatrix(f.h));
  d["coherence"] = f.coherence.size() > 0 ? py::object(matrix_to_numpy(Matrix(f.coherence))) : py::object(py::none());
  py::list q, units;
  for (auto x : f.quantity) {
    q.append(quantity_name(x));
    units.append(ident::unit_of_quantity(x));
  }
  d["responses"] = f.responses;
  d["quantities"] = q;
  d["units"] = units;
  d["force_unit"] = f.force_unit;
  return d;
}

// The dict of frf_dict back to an Frf (checked as a frf.csv is).
ident::Frf frf_of(const py::dict& d) {
  ident::Frf f;
  py::array_t<double, py::array::forcecast> fr = py::array_t<double, py::array::forcecast>::ensure(d["frequency_hz"]);
  auto h = py::array_t<std::complex<double>, py::array::forcecast>::ensure(d["h"]);
  if (!fr || !h || fr.ndim() != 1 || h.ndim() != 2 || h.shape(0) != fr.shape(0))
    throw InputError("frf: frequency_hz (1-D) and h (frequencies x responses, complex) must agree");
  f.frequency_hz = Eigen::Map<const Vector>(fr.data(), fr.shape(0));
  f.h.resize(h.shape(0), h.shape(1));
  auto hv = h.unchecked<2>();
  for (Index i = 0; i < f.h.rows(); ++i)
    for (Index j = 0; j < f.h.cols(); ++j) f.h(i, j) = hv(i, j);
  f.responses = d["responses"].cast<std::vector<std::string>>();
  for (const auto& u : d["units"].cast<std::vector<std::string>>()) f.quantity.push_back(ident::quantity_of_unit(u));
  f.force_unit = d["force_unit"].cast<std::string>();
  f.check("frf");
  return f;
}

py::dict estimate(const py::handle& force, const py::handle& responses, double fs_hz, const std::vector<std::string>& units,
                  const std::vector<std::string>& names, const std::string& force_unit, const std::string& method,
                  const std::string& estimator, Index nperseg, const std::string& window, std::optional<double> f_min_hz,
                  std::optional<double> f_max_hz, const std::vector<std::tuple<double, double, double>>& steps, double settle_cycles,
                  double t0_s) {
  io::FrfInputs in;
  ContiguousArray keep;
  in.force = view(force, keep, "frf: force");
  in.responses = matrix_of(responses, "frf: responses");
  if (units.size() != static_cast<std::size_t>(in.responses.cols()))
    throw InputError("frf: " + std::to_string(units.size()) + " response units for " + std::to_string(in.responses.cols()) + " responses");
  if (force_unit != "N" && force_unit != "kN") throw InputError("frf: force_unit must be N or kN, got '" + force_unit + "'");
  in.force_unit = force_unit;
  in.force_channel = "force_" + force_unit;
  for (std::size_t j = 0; j < units.size(); ++j) {
    ident::quantity_of_unit(units[j]);  // m, mps or mps2, else the CLI's error
    const std::string base = j < names.size() ? names[j] : "r" + std::to_string(j + 1);
    in.response_channels.push_back(base + "_" + units[j]);
    in.response_units.push_back(units[j]);
  }
  in.fs_hz = fs_hz;
  in.t0_s = t0_s;
  ident::FrfEstimateOptions eo;
  eo.method = ident::frf_method(method, "method");
  if (estimator != "h1" && estimator != "h2") throw InputError("estimator must be h1 or h2, got '" + estimator + "'");
  eo.h2 = estimator == "h2";
  eo.welch.nperseg = nperseg;
  eo.welch.window = viaduct::signal::window_of(window);
  eo.f_min_hz = f_min_hz;
  eo.f_max_hz = f_max_hz;
  for (const auto& [a, b, f] : steps) eo.steps.push_back({a, b, f});
  eo.stepped.settle_cycles = settle_cycles;
  ident::FrfEstimate e;
  {
    py::gil_scoped_release nogil;
    e = ident::estimate_frf(in.force, in.responses, in.fs_hz, in.t0_s, eo);
  }
  io::label_frf(e.frf, in);
  py::dict d = frf_dict(e.frf);
  d["n_segments"] = e.n_segments;
  py::list used;
  for (const auto& s : e.steps) used.append(py::make_tuple(s.t_start_s, s.t_end_s, s.frequency_hz));
  d["steps"] = used;
  return d;
}

// modes.csv's rows (method, mode, frequency_hz, damping_ratio, response, note), stabilization.csv's,
// and the warnings.
py::dict fit(const py::dict& frf, const ident::ModalFitOptions& o) {
  const ident::Frf f = frf_of(frf);
  ident::ModalFitResult r;
  {
    py::gil_scoped_release nogil;
    r = ident::modal_fit(f, o);
  }
  py::dict modes;
  std::vector<std::string> method, response, note;
  std::vector<long> mode;
  std::vector<double> freq, zeta;
  for (const auto& [name, list] : {std::pair<const char*, const std::vector<ident::IdentifiedMode>*>{"peak-picking", &r.peak_picking},
                                   {"circle-fit", &r.circle_fit},
                                   {"lscf-diagram", &r.lscf.diagram_modes},
                                   {"lscf", &r.lscf.modes}})
    for (std::size_t k = 0; k < list->size(); ++k) {
      const ident::IdentifiedMode& m = (*list)[k];
      method.push_back(name);
      mode.push_back(static_cast<long>(k + 1));
      freq.push_back(m.frequency_hz);
      zeta.push_back(m.damping_ratio);
      response.push_back(m.response >= 0 ? f.responses[static_cast<std::size_t>(m.response)] : "all");
      note.push_back(m.note);
    }
  modes["method"] = method;
  modes["mode"] = mode;
  modes["frequency_hz"] = to_numpy(std::move(freq));
  modes["damping_ratio"] = to_numpy(std::move(zeta));
  modes["response"] = response;
  modes["note"] = note;
  py::dict stab;
  std::vector<long> order;
  std::vector<double> sf, sz;
  std::vector<std::string> status;
  for (const auto& p : r.lscf.poles) {
    order.push_back(p.order);
    sf.push_back(p.frequency_hz);
    sz.push_back(p.damping_ratio);
    status.push_back(p.status == ident::PoleStatus::stable ? "stable" : p.status == ident::PoleStatus::stable_frequency ? "frequency" : "new");
  }
  stab["order"] = order;
  stab["frequency_hz"] = to_numpy(std::move(sf));
  stab["damping_ratio"] = to_numpy(std::move(sz));
  stab["status"] = status;
  py::list shapes;
  for (const auto& m : r.lscf.modes) shapes.append(py::cast(std::vector<std::complex<double>>(m.shape.data(), m.shape.data() + m.shape.size())));
  py::dict d;
  d["modes"] = modes;
  d["stabilization"] = stab;
  d["lscf_shapes"] = shapes;
  d["warnings"] = r.warnings;
  return d;
}

py::dict decay(const py::handle& x, double fs_hz, double t0_s, const ident::DecayOptions& o) {
  ContiguousArray keep;
  const Vector in = view(x, keep, "decay");
  ident::DecayResult r;
  {
    py::gil_scoped_release nogil;
    r = ident::analyse_decay(in, fs_hz, t0_s, o);
  }
  py::dict d;
  d["start_s"] = r.start_s;
  d["start_detected"] = r.start_detected;
  d["end_s"] = r.end_s;
  d["n_cycles"] = r.n_cycles;
  d["frequency_hz"] = r.frequency_hz;
  d["zeta_log_decrement"] = r.zeta_log_decrement;
  d["zeta_envelope_fit"] = r.zeta_envelope_fit;
  d["envelope_residual"] = r.envelope_residual;
  d["zeta_hilbert"] = r.zeta_hilbert;
  d["frequency_hilbert_hz"] = r.frequency_hilbert_hz;
  d["amplitude_start"] = r.amplitude_start;
  d["amplitude_end"] = r.amplitude_end;
  d["law_zeta0"] = r.law_zeta0;
  d["law_zeta_slope"] = r.law_zeta_slope;
  d["law_f0_hz"] = r.law_f0_hz;
  d["law_f_slope_hz"] = r.law_f_slope_hz;
  std::vector<double> t, a, f, z;
  for (const auto& p : r.by_amplitude) {
    t.push_back(p.t_s);
    a.push_back(p.amplitude);
    f.push_back(p.frequency_hz);
    z.push_back(p.damping_ratio);
  }
  py::dict w;
  w["t_s"] = to_numpy(std::move(t));
  w["amplitude"] = to_numpy(std::move(a));
  w["frequency_hz"] = to_numpy(std::move(f));
  w["damping_ratio"] = to_numpy(std::move(z));
  d["by_amplitude"] = w;
  return d;
}

py::dict peaks(const py::handle& y, double min_height, double min_prominence, Index min_distance, std::size_t max_peaks,
               const std::string& interpolation) {
  namespace signal = viaduct::signal;
  ContiguousArray keep;
  const Vector in = view(y, keep, "peaks");
  signal::PeakOptions o;
  o.min_height = min_height;
  o.min_prominence = min_prominence;
  o.min_distance = min_distance;
  o.max_peaks = max_peaks;
  signal::Interpolation how = signal::Interpolation::gaussian;
  if (interpolation == "none") how = signal::Interpolation::none;
  else if (interpolation == "parabolic") how = signal::Interpolation::parabolic;
  else if (interpolation != "gaussian") throw InputError("interpolation must be gaussian, parabolic or none, got '" + interpolation + "'");
  std::vector<long> index;
  std::vector<double> position, value, prominence;
  for (const auto& p : signal::find_peaks(in, o, how)) {
    index.push_back(static_cast<long>(p.index));
    position.push_back(p.position);
    value.push_back(p.value);
    prominence.push_back(p.prominence);
  }
  py::dict d;
  d["index"] = index;
  d["position"] = to_numpy(std::move(position));
  d["value"] = to_numpy(std::move(value));
  d["prominence"] = to_numpy(std::move(prominence));
  return d;
}

py::dict speed(const py::handle& x, double fs_hz, double distance_m, const std::string& method, double v_min_kmh, double v_max_kmh,
               int harmonics, double min_interval_s) {
  namespace study = viaduct::study;
  ContiguousArray keep;
  const Vector in = view(x, keep, "identify_speed");
  study::SpeedEstimate e;
  if (method == "spectrum") e = study::speed_from_spectrum(in, fs_hz, distance_m, v_min_kmh / 3.6, v_max_kmh / 3.6, harmonics);
  else if (method == "peaks") e = study::speed_from_peaks(in, fs_hz, distance_m, min_interval_s, v_min_kmh / 3.6, v_max_kmh / 3.6);
  else throw InputError("method must be spectrum or peaks, got '" + method + "'");
  py::dict d;
  d["speed_kmh"] = e.speed * 3.6;
  d["uncertainty_kmh"] = e.uncertainty * 3.6;
  d["frequency_hz"] = e.frequency_hz;
  d["n_used"] = e.n_used;
  return d;
}

// One window of ident::identify_output_only as a dict (the columns of viaduct oma's tables).
py::dict oma_window(const ident::OmaWindow& w) {
  py::dict d;
  d["t_start_s"] = w.t_start_s;
  d["t_end_s"] = w.t_end_s;
  d["error"] = w.error;
  d["warning"] = w.warning;
  d["block_rows"] = w.ssi.block_rows;
  std::vector<double> f, z, sf, sz, spf, spz, mpc, mpd;
  std::vector<long> order, n_poles;
  std::vector<std::string> note;
  const Index n_ch = w.ssi.modes.empty() ? 0 : w.ssi.modes.front().shape.size();
  ident::ComplexMatrix shapes(n_ch, static_cast<Index>(w.ssi.modes.size()));
  for (std::size_t k = 0; k < w.ssi.modes.size(); ++k) {
    const ident::OmaMode& m = w.ssi.modes[k];
    f.push_back(m.frequency_hz), z.push_back(m.damping_ratio), sf.push_back(m.frequency_std_hz), sz.push_back(m.damping_std);
    spf.push_back(m.frequency_spread_hz), spz.push_back(m.damping_spread), mpc.push_back(m.mpc), mpd.push_back(m.mpd_deg);
    order.push_back(m.order), n_poles.push_back(static_cast<long>(m.n_poles)), note.push_back(m.note);
    shapes.col(static_cast<Index>(k)) = m.shape;
  }
  py::dict modes;
  modes["frequency_hz"] = to_numpy(std::move(f));
  modes["damping_ratio"] = to_numpy(std::move(z));
  modes["frequency_std_hz"] = to_numpy(std::move(sf));
  modes["damping_std"] = to_numpy(std::move(sz));
  modes["frequency_spread_hz"] = to_numpy(std::move(spf));
  modes["damping_spread"] = to_numpy(std::move(spz));
  modes["mpc"] = to_numpy(std::move(mpc));
  modes["mpd_deg"] = to_numpy(std::move(mpd));
  modes["order"] = order;
  modes["n_poles"] = n_poles;
  modes["note"] = note;
  d["modes"] = modes;
  d["shapes"] = matrix_to_numpy(std::move(shapes));
  std::vector<long> p_order, p_mode;
  std::vector<double> pf, pz, pmpc, pmpd;
  std::vector<std::string> status;
  for (const auto& p : w.ssi.poles) {
    p_order.push_back(p.order), pf.push_back(p.frequency_hz), pz.push_back(p.damping_ratio), pmpc.push_back(p.mpc);
    pmpd.push_back(p.mpd_deg), status.push_back(ident::pole_status(p)), p_mode.push_back(p.cluster + 1);
  }
  py::dict poles;
  poles["order"] = p_order;
  poles["frequency_hz"] = to_numpy(std::move(pf));
  poles["damping_ratio"] = to_numpy(std::move(pz));
  poles["mpc"] = to_numpy(std::move(pmpc));
  poles["mpd_deg"] = to_numpy(std::move(pmpd));
  poles["status"] = status;
  poles["mode"] = p_mode;  // 0: in no mode's cluster
  d["poles"] = poles;
  py::dict fdd;
  fdd["frequency_hz"] = to_numpy(Vector(w.fdd.frequency_hz));
  fdd["singular_values"] = matrix_to_numpy(Matrix(w.fdd.singular_values));
  std::vector<double> ff, ef, ez;
  for (const auto& m : w.fdd.modes) ff.push_back(m.frequency_hz), ef.push_back(m.efdd_frequency_hz), ez.push_back(m.efdd_damping_ratio);
  fdd["peak_hz"] = to_numpy(std::move(ff));
  fdd["efdd_frequency_hz"] = to_numpy(std::move(ef));
  fdd["efdd_damping_ratio"] = to_numpy(std::move(ez));
  d["fdd"] = fdd;
  return d;
}

py::list oma(const py::handle& y, double fs_hz, double t0_s, std::vector<std::string> names, const ident::OmaPlan& plan) {
  const Matrix data = matrix_of(y, "oma");
  if (names.empty())
    for (Index c = 0; c < data.cols(); ++c) names.push_back("channel " + std::to_string(c + 1));
  if (static_cast<Index>(names.size()) != data.cols())
    throw InputError("oma: " + std::to_string(names.size()) + " names for " + std::to_string(data.cols()) + " channels");
  std::vector<ident::OmaWindow> windows;
  {
    py::gil_scoped_release nogil;
    windows = ident::identify_output_only(data, fs_hz, t0_s, names, plan);
  }
  py::list out;
  for (const auto& w : windows) out.append(oma_window(w));
  return out;
}

}  // namespace

void bind_ident(py::module_& m) {
  m.def("peaks", &peaks, py::arg("y"), py::arg("min_height") = -std::numeric_limits<double>::infinity(),
        py::arg("min_prominence") = 0.0, py::arg("min_distance") = 1, py::arg("max_peaks") = 0, py::arg("interpolation") = "gaussian");
  m.def("identify_speed", &speed, py::arg("x"), py::arg("fs_hz"), py::arg("distance_m"), py::arg("method") = "spectrum",
        py::arg("v_min_kmh") = 40.0, py::arg("v_max_kmh") = 400.0, py::arg("harmonics") = 4, py::arg("min_interval_s") = 0.1);
  m.def("frf", &estimate, py::arg("force"), py::arg("responses"), py::arg("fs_hz"), py::arg("units"),
        py::arg("names") = std::vector<std::string>{}, py::arg("force_unit") = "N", py::arg("method") = "welch",
        py::arg("estimator") = "h1", py::arg("nperseg") = 4096, py::arg("window") = "hann", py::arg("f_min_hz") = py::none(),
        py::arg("f_max_hz") = py::none(), py::arg("steps") = std::vector<std::tuple<double, double, double>>{},
        py::arg("settle_cycles") = 30.0, py::arg("t0_s") = 0.0);
  m.def(
      "modal_fit",
      [](const py::dict& frf, double f_min_hz, double f_max_hz, int max_order, double cluster_tol, double min_prominence, bool refine) {
        ident::ModalFitOptions o;
        o.f_min_hz = f_min_hz;
        o.f_max_hz = f_max_hz;
        o.max_order = max_order;
        o.cluster_tol = cluster_tol;
        o.min_relative_prominence = min_prominence;
        o.refine = refine;
        return fit(frf, o);
      },
      py::arg("frf"), py::arg("f_min_hz") = 0.0, py::arg("f_max_hz") = 1e9, py::arg("max_order") = 40, py::arg("cluster_tol") = 0.005,
      py::arg("min_prominence") = 0.05, py::arg("refine") = true);
  m.def("read_frf", [](const std::string& path) { return frf_dict(io::read_frf_csv(path)); }, py::arg("path"));
  m.def(
      "decay",
      [](const py::handle& x, double fs_hz, double frequency_hz, double t0_s, double band_ratio, int order, std::optional<double> start_s,
         std::optional<double> end_s) {
        ident::DecayOptions o;
        o.frequency_hz = frequency_hz;
        o.band_ratio = band_ratio;
        o.filter_order = order;
        if (start_s) o.start_s = *start_s;
        if (end_s) o.end_s = *end_s;
        return decay(x, fs_hz, t0_s, o);
      },
      py::arg("x"), py::arg("fs_hz"), py::arg("frequency_hz"), py::arg("t0_s") = 0.0, py::arg("band_ratio") = 0.15, py::arg("order") = 2,
      py::arg("start_s") = py::none(), py::arg("end_s") = py::none());
  py::class_<ident::OmaPlan>(m, "OmaPlan")
      .def(py::init<>())
      .def_readwrite("decimate", &ident::OmaPlan::decimate)
      .def_readwrite("start_s", &ident::OmaPlan::start_s)
      .def_readwrite("end_s", &ident::OmaPlan::end_s)
      .def_readwrite("window_s", &ident::OmaPlan::window_s)
      .def_readwrite("min_periods", &ident::OmaPlan::min_periods)
      .def_readwrite("decay_rms_s", &ident::OmaPlan::decay_rms_s)
      .def_property(
          "ssi", [](ident::OmaPlan& p) -> ident::SsiOptions& { return p.ssi; }, [](ident::OmaPlan& p, const ident::SsiOptions& s) { p.ssi = s; },
          py::return_value_policy::reference_internal)
      .def_property(
          "fdd", [](ident::OmaPlan& p) -> ident::FddOptions& { return p.fdd; }, [](ident::OmaPlan& p, const ident::FddOptions& f) { p.fdd = f; },
          py::return_value_policy::reference_internal);
  py::class_<ident::SsiOptions>(m, "SsiOptions")
      .def(py::init<>())
      .def_readwrite("f_min_hz", &ident::SsiOptions::f_min_hz)
      .def_readwrite("f_max_hz", &ident::SsiOptions::f_max_hz)
      .def_readwrite("references", &ident::SsiOptions::references)
      .def_readwrite("block_rows", &ident::SsiOptions::block_rows)
      .def_readwrite("min_order", &ident::SsiOptions::min_order)
      .def_readwrite("max_order", &ident::SsiOptions::max_order)
      .def_readwrite("order_step", &ident::SsiOptions::order_step)
      .def_readwrite("free_decay", &ident::SsiOptions::free_decay)
      .def_readwrite("tol_frequency", &ident::SsiOptions::tol_frequency)
      .def_readwrite("tol_damping", &ident::SsiOptions::tol_damping)
      .def_readwrite("tol_mac", &ident::SsiOptions::tol_mac)
      .def_readwrite("max_damping", &ident::SsiOptions::max_damping)
      .def_readwrite("min_mpc", &ident::SsiOptions::min_mpc)
      .def_readwrite("max_mpd_deg", &ident::SsiOptions::max_mpd_deg)
      .def_readwrite("cluster_distance", &ident::SsiOptions::cluster_distance)
      .def_readwrite("min_cluster_fraction", &ident::SsiOptions::min_cluster_fraction)
      .def_readwrite("jackknife_blocks", &ident::SsiOptions::uncertainty_blocks);
  py::class_<ident::FddOptions>(m, "FddOptions")
      .def(py::init<>())
      .def_readwrite("nperseg", &ident::FddOptions::nperseg)
      .def_readwrite("min_prominence_db", &ident::FddOptions::min_prominence_db)
      .def_readwrite("efdd_mac", &ident::FddOptions::efdd_mac);
  m.def("oma", &oma, py::arg("y"), py::arg("fs_hz"), py::arg("t0_s"), py::arg("names"), py::arg("plan"));
  m.def(
      "track_modes",
      [](const py::list& windows, double tol_frequency, double min_mac) {
        // Each window: (frequencies, shapes) with shapes channels x modes (complex), or None.
        std::vector<std::vector<ident::OmaMode>> w;
        for (const py::handle& item : windows) {
          const auto pair = item.cast<py::tuple>();
          if (pair.size() != 2) throw InputError("track_modes: each window is (frequencies, shapes)");
          const auto f = pair[0].cast<std::vector<double>>();
          std::vector<ident::OmaMode> modes(f.size());
          if (!pair[1].is_none()) {
            using CArray = py::array_t<std::complex<double>, py::array::f_style | py::array::forcecast>;
            const auto a = CArray::ensure(pair[1]);
            if (!a || a.ndim() != 2 || static_cast<std::size_t>(a.shape(1)) != f.size())
              throw InputError("track_modes: shapes must be a 2-D array of channels x modes, one column per frequency");
            const Eigen::Map<const ident::ComplexMatrix> shapes(a.data(), a.shape(0), a.shape(1));
            for (std::size_t k = 0; k < f.size(); ++k) modes[k].shape = shapes.col(static_cast<Index>(k));
          }
          for (std::size_t k = 0; k < f.size(); ++k) modes[k].frequency_hz = f[k];
          w.push_back(std::move(modes));
        }
        ident::TrackingOptions o;
        o.tol_frequency = tol_frequency;
        o.min_mac = min_mac;
        return ident::track_modes(w, o);
      },
      py::arg("windows"), py::arg("tol_frequency") = 0.05, py::arg("min_mac") = 0.8);
}

}  // namespace viaduct_py

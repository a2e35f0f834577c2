// The integration interface: the time grid, the summary, and the three integrators behind
// make_integrator() (docs/architecture.md).
#include "viaduct/solve/integrator.hpp"

#include <cmath>

#include "modal_peaks.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/options.hpp"

namespace viaduct::solve {

Index TimeGrid::n_steps() const { return static_cast<Index>(std::ceil(t_end / dt - 1e-9)); }

bool TimeGrid::is_valid(std::string* why) const {
  OptionsCheck c("TimeGrid", why);
  return c.require(dt > 0.0, "dt", dt, "dt > 0 [s]") && c.require(t_end > 0.0, "t_end", t_end, "t_end > 0 [s]") &&
         c.require(t_end / dt <= 2e9, "t_end", t_end,
                   "t_end/dt <= 2e9 steps (dt = " + format_number(dt, 6) + " s)");
}

const char* kernel_name(Kernel k) {
  switch (k) {
    case Kernel::none: return "none";
    case Kernel::newmark: return "newmark";
    case Kernel::newmark_batch: return "newmark-batch";
    case Kernel::modal: return "modal";
    case Kernel::modal_complex: return "modal-complex";
    case Kernel::modal_peaks: return "modal-peaks";
    case Kernel::ida: return "ida";
    case Kernel::newmark_vehicles: return "newmark-vehicles";
    case Kernel::modal_vehicles: return "modal-vehicles";
    case Kernel::ida_vehicles: return "ida-vehicles";
  }
  throw std::logic_error("kernel_name: unknown kernel");
}

std::string Summary::describe() const {
  if (kernel != Kernel::ida && kernel != Kernel::ida_vehicles) return stop_reason;
  return stop_reason + " (" + std::to_string(n_steps) + " internal steps, " + std::to_string(n_residuals) +
         " residuals, " + std::to_string(n_factorisations) + " factorisations, " + std::to_string(n_rejected_steps) +
         " error-test and " + std::to_string(n_nonlinear_failures) + " Newton failures, " +
         std::to_string(n_restarts) + " restarts)";
}

const char* method_name(Method m) {
  switch (m) {
    case Method::newmark: return "newmark";
    case Method::modal: return "modal";
    case Method::ida: return "ida";
  }
  throw std::logic_error("method_name: unknown method");
}

// (here, not in ida.cpp: a build without SUNDIALS checks the options too)
bool IdaOptions::is_valid(std::string* why) const {
  OptionsCheck c("IdaOptions", why);
  return c.require(rtol >= 1e-12 && rtol <= 0.1, "rtol", rtol, "rtol in [1e-12, 0.1]") &&
         c.require(atol_disp > 0.0, "atol_disp", atol_disp, "atol_disp > 0 [m]") &&
         c.require(atol_vel > 0.0, "atol_vel", atol_vel, "atol_vel > 0 [m/s]") &&
         c.require(max_order >= 1 && max_order <= 5, "max_order", max_order, "max_order in 1..5") &&
         c.require(max_step >= 0.0, "max_step", max_step, "max_step >= 0 [s]") &&
         c.require(max_steps_per_output >= 1, "max_steps_per_output", static_cast<double>(max_steps_per_output),
                   "max_steps_per_output >= 1");
}

bool IntegrationSettings::is_valid(std::string* why) const {
  OptionsCheck c("IntegrationSettings", why);
  if (!c.require(dt > 0.0, "dt", dt, "dt > 0 [s]")) return false;
  switch (method) {
    case Method::newmark: return newmark.is_valid(why);
    case Method::modal: return modal.is_valid(why);
    case Method::ida: return ida.is_valid(why);
  }
  return c.fail("method", std::to_string(static_cast<int>(method)), "one of newmark, modal, ida");
}

std::vector<CaseResult> Integrator::run_batch(const std::vector<LoadCase>& cases, const Recording& rec) const {
  std::vector<CaseResult> out;
  out.reserve(cases.size());
  for (const LoadCase& c : cases) out.push_back(run(c, rec));
  return out;
}

namespace {

// Refuses histories of n_series series beyond the recording's limit.
void check_history_size(const TimeGrid& g, std::size_t n_series, const Recording& rec) {
  const double n_samples = static_cast<double>(g.n_steps()) + 1.0;
  if (n_samples * static_cast<double>(n_series) * sizeof(double) > rec.max_history_bytes)
    throw InputError("a run of " + format_number(g.t_end, 6) + " s at dt = " + format_number(g.dt, 6) +
                     " s would record " + format_number(n_samples, 6) + " samples of " + std::to_string(n_series) +
                     " series: more than " + format_number(rec.max_history_bytes / (1 << 30), 3) +
                     " GiB; raise the speed or analysis.dt");
}

// Histories sized for a case (every rec.stride-th step), refused beyond the recording's limit.
void allocate(CaseResult& r, const TimeGrid& g, std::size_t n_outputs, const Recording& rec) {
  if (rec.stride < 1) throw InputError("recording: stride must be >= 1");
  const TimeGrid kept{g.dt * static_cast<double>(rec.stride), g.t_end};
  check_history_size(kept, n_outputs * ((rec.disp_history ? 1 : 0) + (rec.acc_history ? 1 : 0) + (rec.vel_history ? 1 : 0)), rec);
  const auto rows = g.n_steps() / rec.stride + 1, cols = static_cast<Index>(n_outputs);
  if (rec.disp_history) r.disp.resize(rows, cols);
  if (rec.acc_history) r.acc.resize(rows, cols);
  if (rec.vel_history) r.vel.resize(rows, cols);
  r.max_abs_disp = Vector::Zero(cols);
  r.max_disp = Vector::Zero(cols);
  r.min_disp = Vector::Zero(cols);
  r.max_abs_acc = Vector::Zero(cols);
}

// Records step k of the outputs (values d, a per output; v when kept), in the histories when k
// is a multiple of the stride.
struct Sampler {
  CaseResult* r;
  Index stride = 1;
  void operator()(Index k, Index j, double d, double a, double v = 0.0) const {
    if (k % stride == 0) {
      const Index i = k / stride;
      if (r->disp.size()) r->disp(i, j) = d;
      if (r->acc.size()) r->acc(i, j) = a;
      if (r->vel.size()) r->vel(i, j) = v;
    }
    r->max_abs_disp[j] = std::max(r->max_abs_disp[j], std::abs(d));
    r->max_disp[j] = std::max(r->max_disp[j], d);
    r->min_disp[j] = std::min(r->min_disp[j], d);
    r->max_abs_acc[j] = std::max(r->max_abs_acc[j], std::abs(a));
  }
};

double eval(const Functional& f, const Vector& u) {
  double w = 0.0;
  for (std::size_t i = 0; i < f.dof.size(); ++i) w += f.weight[i] * u[f.dof[i]];
  return w;
}

void check_outputs(const std::vector<Functional>& outputs, Index n, const char* who) {
  for (const Functional& f : outputs) {
    if (f.dof.size() != f.weight.size()) throw InputError(std::string(who) + ": output with mismatched dofs and weights");
    for (Index d : f.dof)
      if (d < 0 || d >= n) throw InputError(std::string(who) + ": output DOF out of range");
  }
}

const SecondOrderSystem& system_of(const LoadCase& c, const char* who) {
  if (!c.system) throw InputError(std::string(who) + ": a load case without a system");
  return *c.system;
}

// One case of a kernel that delivers the full state (u, v, a) at every sample: the outputs
// evaluated and recorded. kernel(sys, grid, observer) runs it and returns its Summary.
// Sums of outputs (Recording::sums) are kept by the modal peaks kernel alone.
void require_no_sums(const Recording& rec, const char* who) {
  if (!rec.sums.empty())
    throw InputError(std::string(who) +
                     ": sums of outputs are tracked by the modal peaks kernel only (moving loads, no deflection history)");
}

template <class Kernel>
CaseResult run_full_state(const LoadCase& c, double dt, const std::vector<Functional>& outputs, const Recording& rec,
                          const char* who, const std::string& cause, Kernel&& kernel) {
  require_no_sums(rec, who);
  const SecondOrderSystem& sys = system_of(c, who);
  const TimeGrid g{dt, c.t_end};
  require_valid(g, who);
  check_outputs(outputs, sys.n_dofs(), who);
  CaseResult r;
  allocate(r, g, outputs.size(), rec);
  const Sampler put{&r, rec.stride};
  const Index total = g.n_steps(), every = std::max<Index>(1, total / 100);
  r.summary = kernel(sys, g, [&](Index k, double t, const Vector& u, const Vector& v, const Vector& a) {
    for (std::size_t j = 0; j < outputs.size(); ++j) {
      const double d = eval(outputs[j], u);
      if (c.bound) check_output(*c.bound, static_cast<Index>(j), d, t, cause);
      put(k, static_cast<Index>(j), d, eval(outputs[j], a), rec.vel_history ? eval(outputs[j], v) : 0.0);
    }
    if (c.progress && *c.progress && (k % every == 0 || k == total))
      (*c.progress)(static_cast<std::size_t>(k), static_cast<std::size_t>(total));
  });
  return r;
}

// Velocity histories and strides are recorded by run() of the kernels that have the full state.
void require_plain(const Recording& rec, const char* who) {
  require_no_sums(rec, who);
  if (rec.vel_history || rec.stride != 1)
    throw InputError(std::string(who) + ": velocity histories and recording strides are recorded by newmark's and ida's run() only");
}

// The coupled kernels' messages name the kernel that ran.
CoupledSummary named(CoupledSummary s, Kernel kernel) {
  s.summary.kernel = kernel;
  return s;
}

void require_coupled(const CoupledCase& c, const char* who) {
  if (!c.M || !c.C || !c.K || !c.vehicle || !c.path) throw InputError(std::string(who) + ": a coupled case without matrices, vehicle or path");
}

class NewmarkIntegrator : public Integrator {
 public:
  NewmarkIntegrator(const IntegrationSettings& s, std::vector<Functional> outputs)
      : Integrator(std::move(outputs)), dt_(s.dt), opt_(s.newmark) {}
  Method method() const override { return Method::newmark; }
  std::size_t batch_width() const override { return kNewmarkBatch; }

  CaseResult run(const LoadCase& c, const Recording& rec) const override {
    return run_full_state(c, dt_, outputs_, rec, "Newmark", cause(),
                          [&](const SecondOrderSystem& sys, const TimeGrid& g, const StepObserver& observe) {
                            return newmark(sys, g, opt_, observe);
                          });
  }

  Coordinates coupled_coordinates() const override { return Coordinates::physical; }
  CoupledSummary run_coupled(const CoupledCase& c) const override {
    require_coupled(c, "Newmark with vehicles");
    return coupled_newmark(*c.M, *c.C, *c.K, *c.vehicle, *c.path, c.grid, opt_, c.observe, c.bound);
  }

  // Blocks of kNewmarkBatch cases through newmark_batch (one factorisation and every product on
  // four cases at once).
  std::vector<CaseResult> run_batch(const std::vector<LoadCase>& cases, const Recording& rec) const override {
    require_plain(rec, "Newmark batch");
    std::vector<CaseResult> out;
    for (std::size_t first = 0; first < cases.size(); first += kNewmarkBatch) {
      const std::size_t n = std::min(kNewmarkBatch, cases.size() - first);
      std::vector<BatchCase> bc;
      for (std::size_t l = 0; l < n; ++l) {
        const LoadCase& c = cases[first + l];
        bc.push_back({&system_of(c, "Newmark batch"), c.t_end});
        const TimeGrid g{dt_, c.t_end};
        require_valid(g, "Newmark");
        check_history_size(g, 2 * outputs_.size(), rec);  // the kernel keeps both histories
      }
      std::vector<BatchHistories> h = newmark_batch(bc, dt_, opt_, outputs_);
      for (std::size_t l = 0; l < n; ++l) {
        CaseResult r;
        r.max_abs_disp = h[l].disp.cwiseAbs().colwise().maxCoeff().transpose();
        r.max_disp = h[l].disp.colwise().maxCoeff().transpose().cwiseMax(0.0);
        r.min_disp = h[l].disp.colwise().minCoeff().transpose().cwiseMin(0.0);
        r.max_abs_acc = h[l].acc.cwiseAbs().colwise().maxCoeff().transpose();
        if (rec.disp_history) r.disp = std::move(h[l].disp);
        if (rec.acc_history) r.acc = std::move(h[l].acc);
        r.summary = h[l].summary;
        if (cases[first + l].bound) check_maxima(*cases[first + l].bound, r.max_abs_disp, cause());
        out.push_back(std::move(r));
      }
    }
    return out;
  }

 private:
  // What most likely diverged, for the guard's message.
  std::string cause() const {
    return "the time integration, Newmark/HHT with beta = " + format_number(opt_.beta, 6) + ", gamma = " +
           format_number(opt_.gamma, 6) + ", alpha = " + format_number(opt_.alpha, 6) + " at dt = " + format_number(dt_, 6) +
           " s (a scheme or step outside its stability), or a structure that is not held (a mechanism)";
  }
  double dt_;
  NewmarkOptions opt_;
};

#ifdef VIADUCT_HAVE_IDA
class IdaIntegrator : public Integrator {
 public:
  IdaIntegrator(const IntegrationSettings& s, std::vector<Functional> outputs)
      : Integrator(std::move(outputs)), dt_(s.dt), opt_(s.ida) {}
  Method method() const override { return Method::ida; }

  CaseResult run(const LoadCase& c, const Recording& rec) const override {
    return run_full_state(c, dt_, outputs_, rec, "IDA",
                          "IDA's error control (ida.rtol = " + format_number(opt_.rtol, 6) +
                              ", ida.atol_disp, ida.atol_vel), or a structure that is not held (a mechanism)",
                          [&](const SecondOrderSystem& sys, const TimeGrid& g, const StepObserver& observe) {
                            return ida(sys, g, opt_, observe);
                          });
  }

  Coordinates coupled_coordinates() const override { return Coordinates::modal; }
  CoupledSummary run_coupled(const CoupledCase& c) const override {
    require_coupled(c, "IDA with vehicles");
    return coupled_ida(*c.M, *c.C, *c.K, *c.vehicle, *c.path, c.grid, opt_, c.observe, c.bound);
  }

 private:
  double dt_;
  IdaOptions opt_;
};
#endif

class ModalIntegrator : public Integrator {
 public:
  ModalIntegrator(const IntegrationSettings& s, std::size_t n_outputs, std::shared_ptr<const ModalReduction> red)
      : Integrator({}), dt_(s.dt), opt_(s.modal), newmark_(s.newmark), n_out_(n_outputs), red_(std::move(red)) {}
  Method method() const override { return Method::modal; }
  std::size_t batch_width() const override { return 4; }

  // The vehicles' fast path: Newmark on the structure's modes, the vehicles physical.
  Coordinates coupled_coordinates() const override { return Coordinates::modal; }
  CoupledSummary run_coupled(const CoupledCase& c) const override {
    require_coupled(c, "modal superposition with vehicles");
    return named(coupled_newmark(*c.M, *c.C, *c.K, *c.vehicle, *c.path, c.grid, newmark_, c.observe, c.bound), Kernel::modal_vehicles);
  }

  CaseResult run(const LoadCase& c, const Recording& rec) const override {
    reduction();
    if (peaks_only(c, rec)) return run_batch({c}, rec).front();
    require_plain(rec, "modal superposition");
    const TimeGrid g{dt_, c.t_end};
    require_valid(g, "modal superposition");
    CaseResult r;
    allocate(r, g, n_out_, rec);
    const Sampler put{&r};
    auto observe = [&](Index k, double t, const Vector& disp, const Vector& acc) {
      for (std::size_t j = 0; j < n_out_; ++j) {
        const auto jj = static_cast<Index>(j);
        if (c.bound) check_output(*c.bound, jj, disp[jj], t, [this] { return cause(); });
        put(k, jj, disp[jj], acc[jj]);
      }
    };
    if (c.modal_force) r.summary = red_->integrate(*c.modal_force, g, opt_, observe);
    else r.summary = red_->integrate(system_of(c, "modal superposition"), g, opt_, observe);
    return r;
  }

  // Moving loads with peaks-only recording run the fused kernel, four speeds per SIMD pass; other
  // cases one run() each.
  std::vector<CaseResult> run_batch(const std::vector<LoadCase>& cases, const Recording& rec) const override {
    reduction();
    bool fused = !cases.empty();
    for (const LoadCase& c : cases) fused = fused && peaks_only(c, rec) && c.moving == cases.front().moving;
    if (!fused) return Integrator::run_batch(cases, rec);
    if (rec.vel_history || rec.stride != 1) require_plain(rec, "modal superposition");
    std::vector<detail::PeaksCase> pc;
    for (const LoadCase& c : cases) pc.push_back({c.speed, c.t_end});
    std::vector<detail::PeaksCaseResult> pr =
        detail::modal_peaks(*red_, *cases.front().moving, pc, dt_, n_out_, rec.acc_history, rec.max_history_bytes, rec.sums,
                            rec.acc_outputs);
    std::vector<CaseResult> out(pr.size());
    for (std::size_t i = 0; i < pr.size(); ++i) {
      out[i].max_abs_disp = std::move(pr[i].max_abs_disp);
      out[i].max_disp = std::move(pr[i].max_disp);
      out[i].min_disp = std::move(pr[i].min_disp);
      out[i].max_abs_acc = std::move(pr[i].max_abs_acc);
      out[i].max_sum = std::move(pr[i].max_sum);
      out[i].min_sum = std::move(pr[i].min_sum);
      out[i].acc = std::move(pr[i].acc);
      out[i].summary = std::move(pr[i].summary);
      if (cases[i].bound) check_maxima(*cases[i].bound, out[i].max_abs_disp, cause());
    }
    return out;
  }

 private:
  static bool peaks_only(const LoadCase& c, const Recording& rec) { return c.moving && !rec.disp_history; }
  const ModalReduction& reduction() const {
    if (!red_) throw InputError("modal method without a modal model (prepare the model with method = modal)");
    return *red_;
  }
  std::string cause() const {
    return "the modal model (a mode or static correction that is not the structure's) or the load sampling at dt = " +
           format_number(dt_, 6) + " s";
  }
  double dt_;
  ModalOptions opt_;
  NewmarkOptions newmark_;
  std::size_t n_out_;
  std::shared_ptr<const ModalReduction> red_;
};

}  // namespace

#ifndef VIADUCT_HAVE_IDA
constexpr const char* kIdaNotBuilt =
    "this viaduct was built without SUNDIALS IDA (CMake VIADUCT_IDA=OFF, as scripts/demo.sh builds it when "
    "libsundials-dev is not installed): run scripts/setup.sh, then cmake --preset release, cmake --build "
    "--preset release and, for the viaduct on the PATH, cmake --install build/release; or take "
    "analysis.method = \"modal\" or \"newmark\"";
#endif

MethodTraits method_traits(Method m) {
  MethodTraits t;
  switch (m) {
    case Method::newmark: t.batches_histories = true; break;
    case Method::modal: t.needs_reduction = true, t.coupled = Coordinates::modal; break;
    case Method::ida:
      t.coupled = Coordinates::modal;
#ifndef VIADUCT_HAVE_IDA
      t.built = false;
      t.not_built = kIdaNotBuilt;
#endif
      break;
  }
  return t;
}

std::unique_ptr<Integrator> make_integrator(const IntegrationSettings& s, std::vector<Functional> outputs,
                                            std::shared_ptr<const ModalReduction> modal) {
  require_valid(s, "analysis");
  switch (s.method) {
    case Method::newmark: return std::make_unique<NewmarkIntegrator>(s, std::move(outputs));
    case Method::ida:
#ifdef VIADUCT_HAVE_IDA
      return std::make_unique<IdaIntegrator>(s, std::move(outputs));
#else
      throw InputError(std::string("analysis.method = \"ida\": ") + method_traits(Method::ida).not_built);
#endif
    case Method::modal: {
      if (!modal) return std::make_unique<ModalIntegrator>(s, 0, nullptr);  // run_coupled() only
      const std::size_t n = outputs.empty() ? static_cast<std::size_t>(modal->n_outputs()) : outputs.size();
      if (n > static_cast<std::size_t>(modal->n_outputs()))
        throw InputError("modal superposition: more outputs asked for than the modal model has");
      return std::make_unique<ModalIntegrator>(s, n, std::move(modal));
    }
  }
  throw std::logic_error("make_integrator: unknown method");
}

}  // namespace viaduct::solve

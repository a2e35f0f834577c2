#include "viaduct/study/simulation.hpp"

#include <cmath>

#include "viaduct/core/error.hpp"
#include "viaduct/signal/iir.hpp"

namespace viaduct::study {

std::vector<ResolvedStation> resolve_stations(const model::Structure& s,
                                              const std::vector<StationSpec>& specs) {
  if (specs.empty()) throw InputError("at least one station is needed");
  std::vector<ResolvedStation> out;
  for (const auto& sp : specs) {
    ResolvedStation r;
    r.name = sp.name;
    try {
      if (sp.on_deck) {
        r.deck = s.deck_point(sp.span, sp.x_local);
        r.has_deck = true;
        if (s.has_track) {
          r.rail = s.rail_point(s.span_start[sp.span] + sp.x_local);
          r.has_rail = true;
        }
      } else {
        r.rail = s.rail_point(sp.x_track);
        r.has_rail = true;
      }
    } catch (const InputError& e) {
      throw InputError("station '" + sp.name + "': " + e.what());
    }
    out.push_back(r);
  }
  return out;
}

RunResult simulate(const model::Structure& s, const std::vector<ResolvedStation>& stations,
                   const load::Train& train, double speed, const RunSettings& settings) {
  require_positive(speed, "speed [m/s]");
  require_non_negative(settings.free_vibration_s, "free_vibration_s [s]");
  const load::MovingLoads loads(s, train, speed, settings.load_factor);
  const MovingLoadSystem sys(s, loads);
  solve::NewmarkOptions opt = settings.newmark;
  opt.t_end = loads.t_exit() + settings.free_vibration_s;
  std::string why;
  if (!opt.is_valid(&why)) throw InputError("Newmark: " + why);
  const double n_samples_real = std::ceil(opt.t_end / opt.dt - 1e-9) + 1;
  // Every step is recorded: refuse runs whose histories alone would not fit comfortably.
  const double bytes = n_samples_real * static_cast<double>(1 + 4 * stations.size()) * sizeof(double);
  if (bytes > kMaxHistoryBytes)
    throw InputError("a run of " + format_number(opt.t_end, 6) + " s at dt = " + format_number(opt.dt, 6) + " s records " +
                     format_number(n_samples_real, 6) + " samples (" + format_number(bytes / (1 << 30), 3) +
                     " GiB of histories; at most " + format_number(kMaxHistoryBytes / (1 << 30), 3) +
                     " GiB): raise the speed or analysis.dt");
  const auto n_samples = static_cast<Index>(n_samples_real);

  RunResult r;
  r.speed = speed;
  r.t.resize(n_samples);
  for (const auto& st : stations) {
    StationHistory h;
    h.name = st.name;
    h.on_deck = st.has_deck;
    h.disp.resize(n_samples);
    h.acc.resize(n_samples);
    if (st.has_deck && st.has_rail) h.rail_disp.resize(n_samples);
    r.stations.push_back(std::move(h));
  }
  auto observe = [&](Index k, double t, const Vector& u, const Vector&, const Vector& a) {
    r.t[k] = t;
    for (std::size_t i = 0; i < stations.size(); ++i) {
      const ResolvedStation& st = stations[i];
      StationHistory& h = r.stations[i];
      const model::PointCoupling& main = st.has_deck ? st.deck : st.rail;
      h.disp[k] = main.value(u);
      h.acc[k] = main.value(a);
      if (h.rail_disp.size() > 0) h.rail_disp[k] = st.rail.value(u);
    }
  };
  r.summary = solve::newmark(sys, opt, observe);
  if (settings.filter.enabled) {
    const signal::Sos sos = signal::cheby1(settings.filter.cheby, 1.0 / opt.dt);
    for (auto& h : r.stations) h.acc_filt = signal::sosfiltfilt(sos, h.acc);
  }
  return r;
}

std::vector<StationPeaks> peaks(const RunResult& r) {
  std::vector<StationPeaks> out;
  for (const auto& h : r.stations) {
    StationPeaks p;
    const Vector& acc = h.acc_filt.size() > 0 ? h.acc_filt : h.acc;
    const Vector& disp = h.disp;
    p.max_abs_acc = acc.size() ? acc.cwiseAbs().maxCoeff() : 0.0;
    p.max_abs_disp = disp.size() ? disp.cwiseAbs().maxCoeff() : 0.0;
    out.push_back(p);
  }
  return out;
}

}  // namespace viaduct::study

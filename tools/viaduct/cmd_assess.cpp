// viaduct assess: the EN 1991-2 §6.4 / EN 1990 A2 dynamic check of a scenario's bridge
// (docs/assess.md). The plan, the tables and the report are io/assessment.hpp's, the runs and
// the checks study/assessment.hpp's (the Python package calls the same); this file binds the
// options, prints and makes the figures.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>

#include "build_paths.hpp"
#include "cli.hpp"
#include "viaduct/io/assessment.hpp"
#include "viaduct/io/report_html.hpp"
#include "viaduct/io/results.hpp"

namespace viaduct::cli {

namespace {

struct AssessOptions {
  bool plots = true;
  bool pdf = true;
};

// The figures, by scripts/plot/plot_assess.py (Python with matplotlib); false when it cannot run.
bool make_figures(const std::string& out, bool quiet) {
  // VIADUCT_PLOT_DIR, then the installed scripts, then the source tree the tool was built from.
  const char* env = std::getenv("VIADUCT_PLOT_DIR");
  std::string script;
  for (const std::string& dir : {std::string(env ? env : ""), std::string(installed_scripts_dir()),
                                std::string(built_source_dir()) + "/scripts/plot"})
    if (!dir.empty() && std::ifstream(dir + "/plot_assess.py").good()) {
      script = dir + "/plot_assess.py";
      break;
    }
  if (script.empty() || out.find('\'') != std::string::npos) return false;
  // The directory is still being written (its manifest comes last): the script need not check it.
  std::error_code ec;
  const std::string abs = std::filesystem::absolute(out, ec).lexically_normal().string();
  const std::string cmd = "VIADUCT_WRITING='" + (abs.size() > 1 && abs.back() == '/' ? abs.substr(0, abs.size() - 1) : abs) +
                          "' /usr/bin/python3 '" + script + "' '" + out + "'" + (quiet ? " >/dev/null 2>&1" : " >/dev/null");
  return std::system(cmd.c_str()) == 0;
}

void print_checks(const std::vector<study::AssessCheck>& checks) {
  std::printf("\n  %-38s %-24s %14s %14s %7s  %s\n", "check", "quantity", "value", "limit", "util.", "result");
  for (const auto& k : checks)
    std::printf("  %-38s %-24s %14s %14s %7s  %s\n", k.check.c_str(), k.quantity.c_str(), study::shown_value(k.quantity, k.value).c_str(),
                study::shown_value(k.quantity, k.limit).c_str(), study::shown_number(k.utilisation(), 3).c_str(), k.verdict.c_str());
}

void declare_assess(po::options_description& d, AssessOptions& a) {
  d.add_options()("no-plots", po::bool_switch()->notifier([&a](bool v) { a.plots = !v; }),
                  "write report.md without running scripts/plot/plot_assess.py")(
      "no-pdf", po::bool_switch()->notifier([&a](bool v) { a.pdf = !v; }), "write report.html without printing report.pdf");
}

void print_layout(const study::LayoutSensitivity& layout) {
  if (!layout.near || layout.peaks.empty()) return;
  double spread = 0.0;
  for (std::size_t j = 0; j < layout.peaks.front().size(); ++j) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (const auto& row : layout.peaks) lo = std::min(lo, row[j]), hi = std::max(hi, row[j]);
    spread = std::max(spread, hi / lo - 1.0);
  }
  std::printf("\nspans %d and %d: modes %.2f %% apart; the governing peak moves by up to %.1f %% with the sleeper layout "
              "(report.md, track.first_sleeper_offset)\n",
              layout.span_a, layout.span_b, 100 * layout.split, 100 * spread);
}

int run_assess(const Common& o, const AssessOptions& opts) {
  const auto t0 = std::chrono::steady_clock::now();
  io::FlatScenario flat = load_scenario(o);
  study::AssessPlan plan = io::plan_assessment(flat, o.scenario, o.threads);
  print_warnings("assess", plan.warnings);
  for (auto& v : plan.variants) v.scenario.settings.ida.log = log_printer(o.quiet);
  make_out_dir(o.out);
  study::AssessOptions ao;
  ao.threads = o.threads;
  ao.progress = progress_printer("assess", o.quiet);
  const study::AssessResult r = study::run_assessment(std::move(plan), ao);
  const study::AssessPlan& p = r.plan;
  io::write_assessment_tables(o.out, r, o.threads);
  io::Manifest m = start_manifest(o, "assess");
  m.as_run = io::settings_as_run(r.nominal().settings);
  m.warnings = p.warnings;
  m.extra = {{"acceleration_limit_mps2", format_number(p.config.acc_limit)}, {"cutoff_hz", format_number(p.f_cut)},
             {"damping_ratio", format_number(p.zeta)}, {"f3_hz", format_number(p.f3)},
             {"f3_span", std::to_string(p.f3_span)}, {"line_speed_kmh", format_number(p.config.line_speed * 3.6)},
             {"n_cases", std::to_string(r.sweep.summary.n_cases)}, {"n_failed", std::to_string(r.sweep.summary.n_failed)},
             {"threads", std::to_string(o.threads)}};
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  io::write_manifest(o.out + "/manifest.toml", m, flat);
  const bool figures = opts.plots && make_figures(o.out, o.quiet);
  const std::string report = io::assessment_report(r, flat, o.command_line, figures);
  io::write_text_file(o.out + "/report.md", report);
  io::write_text_file(o.out + "/report.html",
                      io::report_html(report, r.nominal().title.empty() ? o.scenario : r.nominal().title, o.out));
  std::vector<std::string> pdf_warnings;
  if (opts.pdf) {
    const std::string chromium = io::find_chromium();
    const std::string err = chromium.empty() ? "Chromium not found (Debian's package chromium; VIADUCT_CHROMIUM names another)"
                                             : io::print_to_pdf(chromium, o.out + "/report.html", o.out + "/report.pdf");
    if (!err.empty()) pdf_warnings.push_back("report.pdf not written: " + err + "; report.html holds the same (--no-pdf skips this)");
  }
  if (!o.quiet) {
    std::printf("assessment: %zu cases (%zu mass case%s), %zu failed, %.1f s; cut-off %.1f Hz, damping %.3f %%\n",
                r.sweep.summary.n_cases, p.variants.size(), p.variants.size() > 1 ? "s" : "", r.sweep.summary.n_failed,
                r.sweep.summary.wall_s, p.f_cut, 100 * p.zeta);
    print_checks(r.checks);
    print_layout(r.layout);
    std::printf("\nwrote %s/report.md, report.html%s%s, checks.csv, envelope.csv, load_effects.csv, phi_dyn.csv\n", o.out.c_str(),
                opts.pdf && pdf_warnings.empty() ? ", report.pdf" : "", figures ? " (with figures)" : "");
  }
  if (opts.plots && !figures)
    print_warnings("assess", {"figures not made (needs /usr/bin/python3 with matplotlib and scripts/plot/plot_assess.py): report.md "
                              "has the tables only; make them with scripts/plot/plot_assess.py " + o.out});
  if (!pdf_warnings.empty()) print_warnings("assess", pdf_warnings);
  return sweep_exit_code("assess", o.scenario, r.sweep);
}

}  // namespace

Command assess_command() {
  Command c = command("assess", "SCENARIO",
                      "the EN 1991-2 dynamic check: HSLM and real trains, speeds to 1.2 x line speed, checks (report.md)");
  c.usage_and_samples =
      "Runs the dynamic check of EN 1991-2 6.4 / EN 1990 A2 on the scenario's bridge (docs/assess.md):\n"
      "HSLM-A1..A10 and the scenario's other trains, speeds up to 1.2 x assess.line_speed_kmh refined\n"
      "around every resonance, damping from Table 6.6 (+ Eq. 6.13), lower and upper mass bounds, the\n"
      "frequency cut-off max(30 Hz, 1.5 f1, f3). Writes OUT/report.md (with PNGs by\n"
      "scripts/plot/plot_assess.py), checks.csv (value, limit, utilisation, governing case, clause),\n"
      "envelope.csv, load_effects.csv, phi_dyn.csv, mass_cases.csv (what each mass case sets), governing.csv,\n"
      "failures.csv and manifest.toml. With vehicle models (train.vehicle = sprung or multibody) also\n"
      "vehicles.csv and two more checks: passenger comfort (car-body acceleration against\n"
      "assess.comfort_level's b_v, EN 1990 A2.4.4.3.1) and wheel unloading (assess.unloading_ratio_limit).\n"
      "The scenario's damping, filter and sweep keys are replaced by the assessment's.\n\n"
      "Sample runs:\n"
      "  viaduct assess scenarios/hslm-simply-supported.toml --set assess.speed_step_kmh=20 --set assess.refine_band=0 --no-plots --out out/assess-hslm\n";
  bind(c, declare_assess, run_assess);
  return c;
}

}  // namespace viaduct::cli

#pragma once
/// \file The file side of the dynamic check (study/assessment.hpp): its plan from the scenario's
/// [assess] keys, and its tables and report. `viaduct assess` and the Python package call these.

#include <string>

#include "viaduct/io/results.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/study/assessment.hpp"

namespace viaduct::io {

/// Reads the [assess] keys of `flat` (InputError naming file, line and key; `scenario` names the
/// file for a key that is missing) and forms the plan: the damping (Table 6.6 + Δζ, or
/// assess.damping_ratio) and the cut-off set on `flat` (bridge.damping, filter.*), the trains
/// (HSLM-A1…A10, HSLM-B for short simply supported spans, the scenario's own), their speeds, and
/// the mass cases. Each train's characteristic distance (a signature over 45 000 wavelengths)
/// is computed on up to `threads` threads.
study::AssessPlan plan_assessment(FlatScenario& flat, const std::string& scenario, int threads = 1);

/// The tables of `r` into the directory `out`: envelope.csv, load_effects.csv, governing.csv,
/// failures.csv, checks.csv, phi_dyn.csv, mass_cases.csv and, with vehicles, vehicles.csv
/// (load_effects.csv formatted on n_threads threads: the same file for any count).
void write_assessment_tables(const std::string& out, const study::AssessResult& r, int n_threads = 1);

/// checks.csv's columns (the numbers unrounded, speed_kmh NaN where no case governs) and
/// phi_dyn.csv's: what the Python package hands over as tables.
std::vector<TableColumn> assessment_check_columns(const std::vector<study::AssessCheck>& checks);
std::vector<TableColumn> assessment_increment_columns(const std::vector<study::AssessIncrement>& inc);

/// report.md's text: summary, inputs, details, the layout sensitivity, notes and provenance
/// (`flat`: the scenario as assessed; `command_line`: how it was run; `figures`: the PNGs of
/// scripts/plot/plot_assess.py are in the report's directory).
std::string assessment_report(const study::AssessResult& r, const FlatScenario& flat, const std::string& command_line,
                              bool figures);

}  // namespace viaduct::io

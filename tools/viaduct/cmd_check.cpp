// viaduct check / viaduct schema
#include <iostream>

#include "cli.hpp"
#include "viaduct/study/guards.hpp"
#include "viaduct/io/sampled.hpp"
#include "viaduct/io/scenario.hpp"
#include "viaduct/model/modes.hpp"
#include "viaduct/model/structure.hpp"

namespace viaduct::cli {

Command check_command() {
  Command c = command("check", "SCENARIO", "validate a scenario and print it resolved, with every default and unit");
  c.usage_and_samples =
      "Prints every key with its value, unit and origin (file:line, --set or default), then\n"
      "the model that the scenario builds. Exit code 2 names file, line and key of a bad input.\n\n"
      "Sample runs:\n"
      "  viaduct check scenarios/old-guadiana-sensitivity.toml\n"
      "  viaduct check scenarios/hslm-simply-supported.toml --set bridge.damping.ratio=0.02\n"
      "  viaduct check scenarios/old-guadiana-sampled.toml\n";
  c.run = [](const Common& o) {
    const io::FlatScenario flat = load_scenario(o);
    const study::Scenario sc = io::to_scenario(flat);
    const auto variants = io::sweep_variants(flat);
    const model::Structure s = model::build_structure(sc.bridge, sc.track);
    std::vector<double> speeds = sc.sweep_speeds;
    if (sc.run_speed) speeds.push_back(*sc.run_speed);
    print_warnings("check", study::scenario_warnings(sc, speeds));
    if (o.quiet) return ok;
    std::cout << io::format_resolved(flat) << "\n# model\n";
    std::cout << "# spans: " << sc.bridge.spans.size() << ", bridge length " << sc.bridge.total_length() << " m\n";
    std::cout << "# DOFs: " << s.n_dofs << " (bridge " << s.n_bridge_dofs << ", track " << s.n_track_dofs << ")\n";
    std::cout << "# first modes:\n" << std::flush;
    print_first_modes(s, model::compute_modes_up_to(s, 6, 0.0), 6, "#   ");
    std::fflush(stdout);
    if (s.has_track)
      std::cout << "# track: " << s.sleeper_x.size() << " sleepers from x = " << s.path_start() << " to "
                << s.path_end() << " m; deck beam mass used " << s.deck_mass_per_m_used << " kg/m\n";
    for (const auto& t : sc.trains)
      std::cout << "# train " << t.name << ": " << t.n_axles() << " axles, " << t.length() << " m first to last, "
                << t.total_load() / 1e3 << " kN\n";
    if (!io::is_sampled(flat)) {
      std::cout << "# sweep: " << sc.sweep_speeds.size() << " speeds x " << sc.trains.size() << " trains x "
                << variants.size() << " variants\n";
      return ok;
    }
    // A sampled study at a glance: the runs, and each key's factor range (1st to 99th percentile).
    const io::SampledStudy st = io::sampled_study(flat);
    std::cout << "# sampled study: " << st.n_total() << " samples (" << flat.at("sweep.sampling").s << " design"
              << (st.spec.sensitivity ? ", Saltelli's: " + std::to_string(st.spec.n) + " x " + std::to_string(st.keys.size() + 2)
                                      : std::string())
              << ") x " << sc.sweep_speeds.size() << " speeds x " << sc.trains.size() << " trains = "
              << st.n_total() * Index(sc.sweep_speeds.size() * sc.trains.size()) << " cases\n";
    for (std::size_t i = 0; i < st.keys.size(); ++i) {
      const study::Distribution& d = st.spec.distributions[i];
      std::cout << "#   " << st.labels[i] << " (" << st.keys[i] << "): " << flat.at("sweep.variants[" + std::to_string(i) + "].distribution").s
                << " factor, 1-99 % in [" << format_number(d.quantile(0.01), 4) << ", " << format_number(d.quantile(0.99), 4) << "]\n";
    }
    return ok;
  };
  return c;
}

Command schema_command() {
  Command c = command("schema", "SCENARIO", "print every scenario key (type, default, unit, constraint, meaning) as Markdown");
  c.needs_scenario = false;
  c.usage_and_samples = "docs/scenarios.md embeds this table.\n\nSample runs:\n  viaduct schema\n";
  c.run = [](const Common&) {
    std::cout << io::schema_markdown();
    return ok;
  };
  return c;
}

}  // namespace viaduct::cli

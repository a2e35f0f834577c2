// viaduct modes
#include <cstdio>
#include <iostream>

#include "cli.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/model/modes.hpp"

namespace viaduct::cli {

Command modes_command() {
  Command c = command("modes", "SCENARIO", "natural frequencies and mode shapes of the assembled structure (modes.csv)");
  struct ModesOptions {
    int n_modes = 20;
  };
  const auto declare = [](po::options_description& d, ModesOptions& m) {
    d.add_options()("n-modes", value(m.n_modes), "number of modes to write (0: all)");
  };
  c.usage_and_samples =
      "Writes OUT/modes.csv: mode,frequency_hz and the mass-normalised shape at every station\n"
      "(deck, and rail when there is track), for the whole model (track included).\n\n"
      "Sample runs:\n"
      "  viaduct modes scenarios/old-guadiana-sensitivity.toml --out out/modes\n"
      "  viaduct modes scenarios/hslm-simply-supported.toml --n-modes 5 --out out/modes-hslm\n";
  const auto body = [](const Common& o, const ModesOptions& opts) {
    const int n = opts.n_modes;
    if (n < 0) throw InputError("--n-modes must be >= 0");
    const io::FlatScenario flat = load_scenario(o);
    const study::Scenario sc = io::to_scenario(flat);
    const model::Structure s = model::build_structure(sc.bridge, sc.track);
    const auto stations = study::resolve_stations(s, sc.stations);
    const model::Modes m = model::compute_modes(s, n);
    make_out_dir(o.out);
    io::write_modes_csv(o.out + "/modes.csv", m, s, stations);
    io::write_manifest(o.out + "/manifest.toml", start_manifest(o, "modes"), flat);
    if (!o.quiet) {
      std::printf("%ld DOFs; first modes:\n", static_cast<long>(s.n_dofs));
      print_first_modes(s, m, 6);
      std::printf("wrote %s/modes.csv\n", o.out.c_str());
    }
    return ok;
  };
  return bound(std::move(c), +declare, +body);
}

}  // namespace viaduct::cli

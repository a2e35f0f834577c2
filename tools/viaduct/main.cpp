// viaduct: railway train–track–bridge dynamics. One executable, git-style subcommands.
#include <algorithm>
#include <cstring>
#include <iostream>
#include <vector>

#include "cli.hpp"
#include "viaduct/core/error.hpp"
#include "viaduct/core/simd.hpp"
#include "viaduct/io/results.hpp"
#include "viaduct/solve/integrator.hpp"
#include "viaduct/study/sampled.hpp"

int main(int argc, char** argv) {
  using namespace viaduct::cli;
  std::vector<Command> commands = {check_command(), modes_command(), run_command(), sweep_command(),
                                         schema_command(), filter_command(), spectrum_command(),
                                         peaks_command(), compare_command(), speed_command(),
                                         resample_command(), envelope_command(), fatigue_command(), inspect_command(), tradeoff_command(),
                                         frf_command(), shaker_command(), modal_fit_command(), decay_command(), oma_command(), fit_command(), assess_command(),
                                         passages_command(), irregularity_command(), ladder_command(), merge_command()};
  const std::vector<Command> others = commands;  // what a manifest may name
  commands.push_back(replay_command(&others));
  auto usage = [&](std::ostream& os) {
    os << "viaduct " << viaduct::io::version() << " — railway train–track–bridge dynamics\n\n"
       << "Usage: viaduct COMMAND SCENARIO|RECORD [options]    (viaduct COMMAND --help for each)\n\nCommands:\n";
    std::size_t width = 0;
    for (const auto& c : commands) width = std::max(width, c.name.size());
    for (const auto& c : commands) os << "  " << c.name << std::string(width + 2 - c.name.size(), ' ') << c.summary << "\n";
  };
  if (argc < 2) {
    usage(std::cerr);
    return usage_error;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    usage(std::cout);
    return ok;
  }
  if (name == "--version") {
    std::cout << "viaduct " << viaduct::io::version();
    // A build without SUNDIALS (scripts/demo.sh's where libsundials-dev is missing) says so.
    if (!viaduct::solve::method_traits(viaduct::solve::Method::ida).built) std::cout << " (without the IDA method)";
    std::cout << "\n";
    return ok;
  }
  // A wrong VIADUCT_SIMD stops every command here (a sweep would otherwise retry its failing
  // blocks one case at a time on the general path and say nothing).
  try {
    viaduct::simd_level();
  } catch (const viaduct::InputError& e) {
    std::cerr << "viaduct " << name << ": error: " << e.what() << "\n";
    return usage_error;
  }
  for (const auto& c : commands)
    if (c.name == name) {
      // Under mpirun (and built with MPI) the ranks share the samples of `viaduct sweep` on a
      // sampled study; any other command would run N times over the same outputs.
      const viaduct::study::MpiWorld w = viaduct::study::mpi_start(&argc, &argv);
      if (w.without_mpi) {
        if (w.rank == 0)
          std::cerr << "viaduct " << name << ": error: started on " << w.size
                    << " MPI ranks, but this viaduct was built without MPI (install libopenmpi-dev and rebuild)\n";
        return usage_error;
      }
      if (w.size > 1 && name != "sweep") {
        if (w.rank == 0)
          std::cerr << "viaduct " << name << ": error: started on " << w.size
                    << " MPI ranks; only viaduct sweep on a sampled study (sweep.mode = \"sample\") runs over MPI\n";
        viaduct::study::mpi_finish();
        return usage_error;
      }
      const int rc = dispatch(c, argc - 1, argv + 1);
      viaduct::study::mpi_finish();
      return rc;
    }
  // The nearest command by edit distance, when near enough to be a typo.
  auto distance = [](const std::string& x, const std::string& y) {
    std::vector<std::size_t> row(y.size() + 1);
    for (std::size_t j = 0; j <= y.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= x.size(); ++i) {
      std::size_t diag = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= y.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (x[i - 1] == y[j - 1] ? 0 : 1)});
        diag = up;
      }
    }
    return row[y.size()];
  };
  std::string best;
  std::size_t best_d = 3;  // at most two edits
  for (const auto& c : commands)
    if (const std::size_t d = distance(name, c.name); d < best_d) best_d = d, best = c.name;
  std::cerr << "viaduct: unknown command '" << name << "'" << (best.empty() ? "" : " (did you mean '" + best + "'?)") << "\n";
  usage(std::cerr);
  return usage_error;
}

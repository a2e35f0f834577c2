// viaduct: railway train–track–bridge dynamics. One executable, git-style subcommands.
#include <cstring>
#include <iostream>
#include <vector>

#include "cli.hpp"
#include "viaduct/io/results.hpp"

int main(int argc, char** argv) {
  using namespace viaduct::cli;
  const std::vector<Command> commands = {check_command(), modes_command(), run_command(), sweep_command(),
                                         schema_command(), filter_command(), spectrum_command(),
                                         peaks_command(), compare_command(), speed_command(),
                                         resample_command(), envelope_command(), tradeoff_command(),
                                         frf_command(), shaker_command(), modal_fit_command(), decay_command(), fit_command()};
  auto usage = [&](std::ostream& os) {
    os << "viaduct " << viaduct::io::version() << " — railway train–track–bridge dynamics\n\n"
       << "Usage: viaduct COMMAND SCENARIO|RECORD [options]    (viaduct COMMAND --help for each)\n\nCommands:\n";
    for (const auto& c : commands) os << "  " << c.name << std::string(11 - c.name.size(), ' ') << c.summary << "\n";
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
    std::cout << "viaduct " << viaduct::io::version() << "\n";
    return ok;
  }
  for (const auto& c : commands)
    if (c.name == name) return dispatch(c, argc - 1, argv + 1);
  std::cerr << "viaduct: unknown command '" << name << "'\n";
  usage(std::cerr);
  return usage_error;
}

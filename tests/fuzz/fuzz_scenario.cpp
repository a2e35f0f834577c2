// Scenario TOML: parsing, every key's type and rule, the conversion to a study::Scenario and the
// sweep's variants.
#include <cmath>
#include <filesystem>

#include "../source_dir.hpp"
#include "harness.hpp"
#include "viaduct/io/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The input stands where the shipped scenarios do, beside a link to the repository's data/, so
  // that their component and train files resolve and the conversion runs to the end.
  static const std::string path = [] {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("viaduct-fuzz-scenario-" + std::to_string(::getpid()));
    fs::create_directories(dir / "scenarios");
    std::error_code ec;
    fs::create_directory_symlink(fs::path(VIADUCT_SOURCE_DIR) / "data", dir / "data", ec);
    return (dir / "scenarios" / "input.toml").string();
  }();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return fuzz::run([&] {
    const viaduct::io::FlatScenario flat = viaduct::io::load_flat(path);
    const viaduct::study::Scenario sc = viaduct::io::to_scenario(flat);
    fuzz::require(!sc.stations.empty(), "a scenario has stations");
    for (double v : sc.sweep_speeds) fuzz::require(v > 0 && std::isfinite(v), "sweep speeds are finite and > 0");
    for (const auto& t : sc.trains) fuzz::require(!t.offset.empty(), "trains have axles");
    const auto variants = viaduct::io::sweep_variants(flat, /*isolate_failures=*/true);
    fuzz::require(!variants.empty() && variants.front().error.empty(), "the reference variant stands");
  });
}

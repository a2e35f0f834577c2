// DESIGN.md §2: modules include each other only in the allowed direction, and third-party
// headers other than Eigen stay in the src/ of the module that wraps them (toml11 in src/io,
// FFTW in src/signal, SUNDIALS/KLU in src/solve, Spectra in src/model, Ceres in src/study),
// Boost.Program_options in tools/viaduct only. Public headers never include a third-party header
// but Eigen's, and kernel-private headers (SIMD lanes) stay out of include/.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include "source_dir.hpp"

namespace fs = std::filesystem;

namespace {
// Where each third-party header family may be included: {top directory, module}.
struct Home {
  const char* prefix;
  const char* top;
  const char* module;
};
const Home kHomes[] = {
    {"toml", "src", "io"},         {"fftw", "src", "signal"},       {"ida/", "src", "solve"},
    {"sundials/", "src", "solve"}, {"nvector/", "src", "solve"},    {"sunlinsol/", "src", "solve"},
    {"sunmatrix/", "src", "solve"}, {"klu", "src", "solve"},        {"Spectra/", "src", "model"},
    {"ceres/", "src", "study"},    {"boost/", "tools", "viaduct"},
};
}  // namespace

TEST_CASE("modules include only what the layering allows") {
  const std::map<std::string, std::set<std::string>> allowed = {
      {"core", {"core"}},
      {"model", {"core", "model"}},
      {"load", {"core", "model", "load"}},
      {"solve", {"core", "solve"}},
      {"signal", {"core", "signal"}},
      {"ident", {"core", "signal", "ident"}},
      {"study", {"core", "model", "load", "solve", "signal", "ident", "study"}},
      {"io", {"core", "model", "load", "solve", "signal", "ident", "study", "io"}},
      // tools/: the CLI and the benchmark programs sit on top of everything.
      {"viaduct", {"core", "model", "load", "solve", "signal", "ident", "study", "io"}},
      {"bench", {"core", "model", "load", "solve", "signal", "ident", "study", "io"}},
  };
  const fs::path root(VIADUCT_SOURCE_DIR);
  const std::regex inc(R"re(#include\s*[<"]([^>"]+)[>"])re");
  int n_files = 0;
  std::set<std::string> tops_seen;
  for (const std::string top : {"include/viaduct", "src", "tools"}) {
    for (const auto& e : fs::recursive_directory_iterator(root / top)) {
      if (!e.is_regular_file()) continue;
      const std::string module = fs::relative(e.path(), root / top).begin()->string();
      INFO(e.path().string());
      REQUIRE(allowed.count(module) == 1);
      std::ifstream in(e.path());
      std::string line;
      ++n_files;
      tops_seen.insert(top);
      while (std::getline(in, line)) {
        std::smatch m;
        if (!std::regex_search(line, m, inc)) continue;
        const std::string h = m[1];
        INFO(h);
        if (h.rfind("viaduct/", 0) == 0) {
          const std::string dep = h.substr(8, h.find('/', 8) - 8);
          REQUIRE(allowed.at(module).count(dep) == 1);
        }
        for (const Home& home : kHomes)
          if (h.rfind(home.prefix, 0) == 0) REQUIRE((top == home.top && module == home.module));
        if (h.find("lanes.hpp") != std::string::npos) REQUIRE((top == "src" && module == "solve"));
        if (top != "tools" && h == "iostream") FAIL("the library is quiet: no iostream in include/ or src/");
      }
    }
  }
  REQUIRE(n_files > 40);
  REQUIRE(tops_seen.size() == 3);
}

TEST_CASE("loading a scenario does not compile the solver API") {
  // io/scenario.hpp and study/scenario.hpp may reach solve/options.hpp (the options a scenario
  // sets) but no kernel header.
  const fs::path root(VIADUCT_SOURCE_DIR);
  const std::regex inc(R"re(#include\s*"(viaduct/[^"]+)")re");
  std::set<std::string> seen;
  std::vector<std::string> todo = {"viaduct/io/scenario.hpp"};
  while (!todo.empty()) {
    const std::string h = todo.back();
    todo.pop_back();
    if (!seen.insert(h).second) continue;
    std::ifstream in(root / "include" / h);
    REQUIRE(in.good());
    std::string line;
    while (std::getline(in, line)) {
      std::smatch m;
      if (std::regex_search(line, m, inc)) todo.push_back(m[1]);
    }
  }
  INFO("headers reached from io/scenario.hpp: " << seen.size());
  REQUIRE(seen.count("viaduct/solve/options.hpp") == 1);
  for (const char* kernel : {"viaduct/solve/newmark.hpp", "viaduct/solve/modal.hpp", "viaduct/solve/ida.hpp",
                             "viaduct/solve/integrator.hpp", "viaduct/study/simulation.hpp"})
    REQUIRE(seen.count(kernel) == 0);
}

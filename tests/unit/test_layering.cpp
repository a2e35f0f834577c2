// DESIGN.md §2: modules include each other only in the allowed direction, and third-party
// headers other than Eigen stay in their own module's src/ (toml11 in src/io, Boost in tools/).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>

namespace fs = std::filesystem;

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
  };
  const fs::path root(VIADUCT_SOURCE_DIR);
  const std::regex inc(R"re(#include\s*[<"]([^>"]+)[>"])re");
  int n_files = 0;
  for (const std::string top : {"include/viaduct", "src"}) {
    for (const auto& e : fs::recursive_directory_iterator(root / top)) {
      if (!e.is_regular_file()) continue;
      const std::string module = fs::relative(e.path(), root / top).begin()->string();
      REQUIRE(allowed.count(module) == 1);
      std::ifstream in(e.path());
      std::string line;
      ++n_files;
      while (std::getline(in, line)) {
        std::smatch m;
        if (!std::regex_search(line, m, inc)) continue;
        const std::string h = m[1];
        INFO(e.path().string() << ": " << h);
        if (h.rfind("viaduct/", 0) == 0) {
          const std::string dep = h.substr(8, h.find('/', 8) - 8);
          REQUIRE(allowed.at(module).count(dep) == 1);
        }
        if (h.rfind("toml", 0) == 0) REQUIRE((top == "src" && module == "io"));
        if (h.rfind("boost/", 0) == 0) FAIL("Boost belongs in tools/ only");
        if (h.rfind("fftw", 0) == 0) REQUIRE((top == "src" && module == "signal"));
        if (h.rfind("ida/", 0) == 0 || h.rfind("sundials/", 0) == 0) REQUIRE((top == "src" && module == "solve"));
        if (h == "iostream") FAIL("the library is quiet: no iostream in include/ or src/");
      }
    }
  }
  REQUIRE(n_files > 20);
}

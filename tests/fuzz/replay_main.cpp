// Runs a fuzz harness without libFuzzer: every file of the corpus directories, then `mutations`
// inputs made from them by seeded random edits (bit flips, bytes inserted, deleted or repeated,
// numbers swapped for extreme ones, lines cut or doubled). The CI's short fuzz run, under the
// sanitizers; scripts/measure/fuzz.sh runs the coverage-guided libFuzzer build for long.
//
//   viaduct_fuzz_replay_<target> [--mutations N] [--seed S] CORPUS_DIR...
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// One random edit of `s` (which may grow or shrink).
void mutate(std::string& s, std::mt19937_64& rng) {
  static const char* const tokens[] = {"1e308", "-1e308", "1e-308", "nan", "inf", "-inf", "0", "-0", "-1",
                                       "4294967296", "9223372036854775808", "1e999", "\"", "[", "]", "=", ",",
                                       "\n", "\r\n", "#", "    -1\n", "\xEF\xBB\xBF", "\t", ";", "[[", "]]"};
  auto pick = [&](std::size_t n) { return n ? static_cast<std::size_t>(rng() % n) : 0; };
  switch (rng() % 8) {
    case 0:  // flip a bit
      if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1u << (rng() % 8));
      break;
    case 1:  // insert a random byte
      s.insert(s.begin() + static_cast<std::ptrdiff_t>(pick(s.size() + 1)), static_cast<char>(rng() % 256));
      break;
    case 2: {  // delete a run
      if (s.empty()) break;
      const std::size_t a = pick(s.size());
      s.erase(a, 1 + pick(std::min<std::size_t>(64, s.size() - a)));
      break;
    }
    case 3: {  // repeat a run
      if (s.empty()) break;
      const std::size_t a = pick(s.size()), n = 1 + pick(std::min<std::size_t>(256, s.size() - a));
      s.insert(a, s.substr(a, n));
      break;
    }
    case 4: {  // a token at a random place
      const char* t = tokens[pick(sizeof tokens / sizeof *tokens)];
      s.insert(pick(s.size() + 1), t);
      break;
    }
    case 5: {  // a number replaced by an extreme one
      std::vector<std::size_t> starts;
      for (std::size_t i = 0; i < s.size(); ++i)
        if (std::isdigit(static_cast<unsigned char>(s[i])) && (i == 0 || !std::isalnum(static_cast<unsigned char>(s[i - 1]))))
          starts.push_back(i);
      if (starts.empty()) break;
      const std::size_t a = starts[pick(starts.size())];
      std::size_t b = a;
      while (b < s.size() && (std::isalnum(static_cast<unsigned char>(s[b])) || s[b] == '.' || s[b] == '-' || s[b] == '+')) ++b;
      s.replace(a, b - a, tokens[pick(12)]);
      break;
    }
    case 6: {  // cut the file at a random place (a torn write)
      s.resize(pick(s.size() + 1));
      break;
    }
    default: {  // a line doubled
      if (s.empty()) break;
      const std::size_t a = s.rfind('\n', pick(s.size()));
      const std::size_t from = a == std::string::npos ? 0 : a + 1;
      const std::size_t to = s.find('\n', from);
      const std::string line = s.substr(from, to == std::string::npos ? std::string::npos : to - from + 1);
      s.insert(from, line);
      break;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  long mutations = 1000;
  unsigned long long seed = 1;
  std::vector<std::string> corpus;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--mutations") && i + 1 < argc) mutations = std::atol(argv[++i]);
    else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) seed = std::strtoull(argv[++i], nullptr, 10);
    else {
      std::error_code ec;
      for (const auto& e : std::filesystem::recursive_directory_iterator(argv[i], ec))
        if (e.is_regular_file()) corpus.push_back(slurp(e.path()));
    }
  }
  if (corpus.empty()) {
    std::fprintf(stderr, "no corpus files\n");
    return 2;
  }
  // Each input is kept in `last` while it runs: after a finding (an abort) it is the reproducer.
  const std::string last =
      (std::filesystem::temp_directory_path() / ("viaduct-fuzz-input-" + std::to_string(::getpid()))).string();
  std::fprintf(stderr, "each input is written to %s before it runs\n", last.c_str());
  auto run = [&](const std::string& s) {
    std::ofstream(last, std::ios::binary | std::ios::trunc) << s;
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
  };
  const auto t0 = std::chrono::steady_clock::now();
  for (const auto& c : corpus) run(c);
  std::mt19937_64 rng(seed);
  for (long k = 0; k < mutations; ++k) {
    std::string s = corpus[rng() % corpus.size()];
    for (int m = 1 + static_cast<int>(rng() % 4); m > 0; --m) mutate(s, rng);
    run(s);
  }
  std::remove(last.c_str());
  std::printf("%zu corpus files and %ld mutations (seed %llu) in %.1f s: no finding\n", corpus.size(), mutations, seed,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return 0;
}

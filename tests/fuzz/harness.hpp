#pragma once
// Shared by the fuzz harnesses (tests/fuzz/fuzz_*.cpp): each defines LLVMFuzzerTestOneInput for
// one parser. Built with libFuzzer (clang, preset `fuzz`, scripts/measure/fuzz.sh) or with the
// mutation replay driver (replay_main.cpp, every compiler: the CI's short run).
//
// A parser may refuse its input — InputError, or SolverError for an I/O failure — and must do
// nothing else: any other exception, a crash, a sanitizer report, a result that breaks the
// reader's promises (a record with a NaN, channels without units, ...) is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>

#include "viaduct/core/error.hpp"

namespace fuzz {

// The input as a file of the given extension (the readers take paths), one per process.
inline std::string as_file(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  static const std::string base = "/tmp/viaduct-fuzz-" + std::to_string(::getpid());
  const std::string path = base + ext;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                 static_cast<std::streamsize>(size));
  return path;
}

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "FUZZ FINDING: %s\n", what.c_str());
  std::abort();
}

// Runs `parse` (which checks its own result with `require`) and sorts what it throws.
template <class F>
int run(F parse) {
  try {
    parse();
  } catch (const viaduct::InputError&) {
  } catch (const viaduct::SolverError&) {
  } catch (const std::exception& e) {
    finding(std::string("unexpected exception: ") + e.what());
  } catch (...) {
    finding("unexpected exception of unknown type");
  }
  return 0;
}

inline void require(bool ok, const char* promise) {
  if (!ok) finding(std::string("broken promise: ") + promise);
}

}  // namespace fuzz

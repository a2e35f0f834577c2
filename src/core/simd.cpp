#include "viaduct/core/simd.hpp"

#include <cstdlib>
#include <string>

#include "viaduct/core/error.hpp"

namespace viaduct {

namespace {
Simd detect_simd() {
  Simd s = Simd::baseline;
#if defined(__GNUC__) && defined(__x86_64__)
  if (__builtin_cpu_supports("avx512f")) s = Simd::avx512;
  else if (__builtin_cpu_supports("avx2")) s = Simd::avx2;
#endif
  if (const char* e = std::getenv("VIADUCT_SIMD"); e && *e) {
    const std::string v = e;
    Simd cap = Simd::avx512;
    if (v == "baseline") cap = Simd::baseline;
    else if (v == "avx2") cap = Simd::avx2;
    else if (v != "avx512")
      throw InputError("environment variable VIADUCT_SIMD = '" + v + "': expected baseline, avx2 or avx512");
    if (cap < s) s = cap;
  }
  return s;
}
}  // namespace

Simd simd_level() {
  static const Simd level = detect_simd();  // an InputError leaves it unset: thrown again next call
  return level;
}

}  // namespace viaduct

// FRF files (viaduct frf's frf.csv) and stepped-sine schedules: what they return passes the
// consistency checks the modal fits rely on.
#include <cmath>

#include "harness.hpp"
#include "viaduct/io/frf.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string path = fuzz::as_file(data + 1, size - 1, ".csv");
  return fuzz::run([&] {
    if (data[0] % 2) {
      const viaduct::ident::Frf f = viaduct::io::read_frf_csv(path);
      f.check("fuzz");
      fuzz::require(f.h.allFinite() && f.frequency_hz.allFinite(), "a finite FRF");
    } else {
      for (const auto& s : viaduct::io::read_steps_csv(path))
        fuzz::require(s.t_end_s > s.t_start_s && s.frequency_hz > 0 && std::isfinite(s.t_end_s), "valid dwells");
    }
  });
}

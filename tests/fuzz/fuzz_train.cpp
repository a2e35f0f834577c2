// Train files: TOML (hslm, regular, axles) or CSV (position_m,load_kN); the first byte of the
// input picks the format.
#include <cmath>

#include "harness.hpp"
#include "viaduct/io/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string path = fuzz::as_file(data + 1, size - 1, data[0] % 2 ? ".csv" : ".toml");
  return fuzz::run([&] {
    const viaduct::load::Train t = viaduct::io::read_train_file(path);
    t.validate();
    fuzz::require(!t.offset.empty() && t.offset.size() <= viaduct::load::kMaxAxles, "1 to kMaxAxles axles");
    for (std::size_t i = 0; i < t.offset.size(); ++i)
      fuzz::require(std::isfinite(t.offset[i]) && t.load[i] > 0 && std::isfinite(t.load[i]), "finite axles, loads > 0");
  });
}

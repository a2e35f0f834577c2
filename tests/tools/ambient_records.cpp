// Writes ambient-vibration records of known modes for the CLI tests of `viaduct oma` (issue #41),
// from the independent generator of tests/unit/ident/ambient.hpp:
//   viaduct_ambient_records DIR N [--minutes M] [--fs F] [--drift D]
// DIR/record_NN.csv, NN = 01..N: three channels acc_a, acc_b, acc_c [m/s²] and temperature_degC,
// three modes (1.5, 3.2, 6.1 Hz; ζ 1, 2, 1.5 %), 5 % sensor noise, the record's time column
// starting at (NN − 1) hours. The frequencies of record k are scaled by 1 + D·(k − 1) (D per
// record, default −0.001: a slow fall, as a bridge warming), the temperature 10 + 0.5·(k − 1) °C.
// DIR.truth.csv (beside the folder): record, mode, frequency_hz, damping_ratio.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "../unit/ident/ambient.hpp"
#include "viaduct/io/record.hpp"
#include "viaduct/io/results.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: viaduct_ambient_records DIR N [--minutes M] [--fs F] [--drift D]\n");
    return 2;
  }
  const std::string dir = argv[1];
  const int n = std::atoi(argv[2]);
  double minutes = 5, fs = 50, drift = -0.001;
  for (int i = 3; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--minutes") minutes = std::atof(argv[i + 1]);
    else if (a == "--fs") fs = std::atof(argv[i + 1]);
    else if (a == "--drift") drift = std::atof(argv[i + 1]);
    else {
      std::fprintf(stderr, "viaduct_ambient_records: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const std::vector<vt::AmbientMode> modes = {{1.5, 0.01, {1.0, 0.7, 0.2}}, {3.2, 0.02, {0.5, -0.6, 1.0}}, {6.1, 0.015, {1.0, -1.0, 0.4}}};
  std::vector<std::vector<std::string>> truth;
  for (int k = 0; k < n; ++k) {
    const double scale = 1.0 + drift * k;
    viaduct::io::Record r;
    r.fs_hz = fs;
    r.t0_s = 3600.0 * k;
    const viaduct::Matrix y = vt::ambient_record(modes, fs, static_cast<viaduct::Index>(minutes * 60 * fs), 0.05, 100u + static_cast<unsigned>(k), scale);
    r.data.resize(y.rows(), 4);
    r.data.leftCols(3) = y;
    r.data.col(3).setConstant(10.0 + 0.5 * k);
    r.channels = {"acc_a_mps2", "acc_b_mps2", "acc_c_mps2", "temperature_degC"};
    r.units = {"mps2", "mps2", "mps2", "degC"};
    char name[64];
    std::snprintf(name, sizeof name, "/record_%02d.csv", k + 1);
    viaduct::io::write_record_csv(dir + name, r, 8);
    for (std::size_t m = 0; m < modes.size(); ++m)
      truth.push_back({name + 1, std::to_string(m + 1), viaduct::io::table_cell(modes[m].f_hz * scale), viaduct::io::table_cell(modes[m].zeta)});
  }
  viaduct::io::write_table_csv(dir + ".truth.csv", {"record", "mode", "frequency_hz", "damping_ratio"}, truth);
  return 0;
}

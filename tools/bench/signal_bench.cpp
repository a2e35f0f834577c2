// Benchmark (not a test): record I/O and signal processing at the sizes of a field campaign.
//   viaduct_signal_bench [--minutes M] [--channels C] [--fs F] [--csv-mb MB] [--dir DIR]
// 1. builds an M-minute, C-channel record at F Hz in memory (decaying sines + noise);
// 2. filters every channel (Chebyshev I order 3, 1-30 Hz, zero phase), computes every channel's
//    Welch PSD (nperseg 8192) and amplitude spectrum;
// 3. writes a CSV of about MB megabytes and reads it back with io::read_record_csv;
// 4. counts the rainflow cycles of 10^7 samples of a band-limited random strain, streamed in
//    blocks of 10^5 (issue #42's target: <= 1 s on one thread), and their Miner sum.
// Prints one "name seconds" line per stage (wall time, one thread).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "viaduct/io/record.hpp"
#include "viaduct/signal/iir.hpp"
#include "viaduct/signal/rainflow.hpp"
#include "viaduct/signal/spectrum.hpp"
#include "viaduct/study/fatigue.hpp"

using namespace viaduct;
using clk = std::chrono::steady_clock;

int main(int argc, char** argv) {
  double minutes = 10, fs = 4096, csv_mb = 100;
  int channels = 18;
  std::string dir = std::filesystem::temp_directory_path().string();
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--minutes") minutes = std::atof(argv[i + 1]);
    else if (a == "--channels") channels = std::atoi(argv[i + 1]);
    else if (a == "--fs") fs = std::atof(argv[i + 1]);
    else if (a == "--csv-mb") csv_mb = std::atof(argv[i + 1]);
    else if (a == "--dir") dir = argv[i + 1];
    else {
      std::fprintf(stderr, "signal_bench: unknown option %s\n", a.c_str());
      return 2;
    }
  }
  const auto n = static_cast<Index>(minutes * 60 * fs);
  io::Record r;
  r.fs_hz = fs;
  r.data.resize(n, channels);
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int c = 0; c < channels; ++c) {
    r.channels.push_back("ch" + std::to_string(c + 1) + "_mps2");
    r.units.push_back("mps2");
    for (Index j = 0; j < n; ++j) {
      const double t = static_cast<double>(j) / fs;
      r.data(j, c) = std::sin(2 * M_PI * (10.0 + c) * t) * std::exp(-0.01 * std::fmod(t, 60.0)) + noise(rng);
    }
  }
  std::printf("record %ld samples x %d channels at %.0f Hz (%.1f min)\n", static_cast<long>(n), channels, fs, minutes);
  auto time = [](const char* name, auto&& fn) {
    const auto t0 = clk::now();
    fn();
    std::printf("%s %.3f\n", name, std::chrono::duration<double>(clk::now() - t0).count());
  };
  signal::Cheby1Spec spec;
  spec.low_hz = 1.0;
  spec.high_hz = 30.0;
  double sink = 0;
  time("filter_all_channels_s", [&] {
    const signal::Sos sos = signal::cheby1(spec, fs);
    for (int c = 0; c < channels; ++c) sink += signal::sosfiltfilt(sos, r.data.col(c))[n / 2];
  });
  time("welch_all_channels_s", [&] {
    signal::WelchOptions o;
    o.nperseg = 8192;
    for (int c = 0; c < channels; ++c) sink += signal::welch(r.data.col(c), fs, o).density[100];
  });
  time("amplitude_spectrum_all_channels_s", [&] {
    for (int c = 0; c < channels; ++c) sink += signal::amplitude_spectrum(r.data.col(c), fs).amplitude[100];
  });
  // A CSV of about csv_mb MB: as many rows of the record as fit (about 12.5 bytes a value).
  const std::string path = dir + "/viaduct-signal-bench.csv";
  io::Record part = r;
  const auto rows = std::min<Index>(n, static_cast<Index>(csv_mb * 1e6 / (12.5 * channels + 13)));
  part.data = r.data.topRows(rows);
  time("write_csv_s", [&] { io::write_record_csv(path, part, 9); });
  const double mb = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
  std::printf("csv_mb %.1f\n", mb);
  time("read_csv_s", [&] { sink += io::read_record_csv(path).data(rows / 2, 0); });
  std::filesystem::remove(path);
  {
    const Index total = 10000000, block = 100000;
    Vector x(block);
    double ar = 0.0, cycles = 0.0;
    std::normal_distribution<double> g(0.0, 20.0);
    study::MinerSum miner(study::SnCurve::en1993_1_9(71), 210e9 * 1e-6);
    std::vector<Vector> blocks;  // generated first: the stage times the counting only
    for (Index k = 0; k < total; k += block) {
      for (Index j = 0; j < block; ++j) x[j] = ar = 0.95 * ar + g(rng);
      blocks.push_back(x);
    }
    time("rainflow_1e7_samples_s", [&] {
      signal::Rainflow rf([&](const signal::Cycle& c) {
        cycles += c.count;
        miner.add(c);
      });
      for (const Vector& b : blocks) rf.push(b);
      rf.finish();
    });
    std::printf("rainflow_cycles %.0f damage %.4g\n", cycles, miner.damage);
    sink += cycles;
  }
  std::printf("checksum %.6g\n", sink);
  return 0;
}

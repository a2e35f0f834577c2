// MATLAB .mat records (issue #19 part 1), read with libmatio from fixtures written by SciPy's
// independent writer (scripts/generate/gen_mat_fixtures.py): vectors with a time vector and a rate
// scalar, a matrix with names and units cell arrays, integer counts with a sampling interval, and
// files that hold no record.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <string>

#include "viaduct/core/error.hpp"
#include "viaduct/io/record.hpp"
#include "../scratch.hpp"
#include "source_dir.hpp"

using namespace viaduct;
using namespace viaduct::io;

namespace {
const std::string mat_dir = std::string(VIADUCT_SOURCE_DIR) + "/tests/data/records/";

std::string mat_error_of(const std::string& path, const ReadOptions& o = {}) {
  try {
    read_record(path, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}
}  // namespace

TEST_CASE("MATLAB .mat: vectors, a time vector, a rate scalar, units converted, a NaN repaired") {
  ImportReport rep;
  const Record r = read_record(mat_dir + "vectors.mat", {}, &rep);
  REQUIRE(r.channels == std::vector<std::string>{"acc_mid_mps2", "disp_mid_m"});
  REQUIRE(r.fs_hz == Approx(250.0).epsilon(1e-12));
  REQUIRE(r.t0_s == Approx(0.5).epsilon(1e-12));
  REQUIRE(r.n_samples() == 50);
  for (int k = 0; k < 50; ++k) {
    // a single-precision row vector in g
    CHECK(r.data(k, 0) == Approx(9.80665 * static_cast<double>(static_cast<float>(0.01 * std::sin(0.3 * k)))).epsilon(1e-12));
    // a column in mm; row 11's NaN interpolated from its neighbours (linear: exact)
    CHECK(r.data(k, 1) == Approx(1e-3 * (1.5 + 0.25 * k)).epsilon(1e-12));
  }
  CHECK(rep.layout.find("MATLAB v5 file, 50 samples in 3 columns") != std::string::npos);
  CHECK(rep.layout.find("not read: calib (3×1, not 50 samples)") != std::string::npos);
  CHECK(rep.time.find("variable 'fs'") != std::string::npos);
  REQUIRE(rep.repairs.size() == 1);
  CHECK(rep.repairs[0].find("disp_mid_m 1") != std::string::npos);
}

TEST_CASE("MATLAB .mat: a matrix with names and units, the rate as Fs, no time vector") {
  const Record r = read_record(mat_dir + "matrix.mat");
  REQUIRE(r.channels == std::vector<std::string>{"acc1_mps2", "strain1_ue", "disp1_m"});
  REQUIRE(r.fs_hz == 100.0);
  REQUIRE(r.t0_s == 0.0);
  for (int k = 0; k < 50; ++k) {
    CHECK(r.data(k, 0) == Approx(9.80665 * 0.02 * std::cos(0.2 * k)).epsilon(1e-12));
    CHECK(r.data(k, 1) == 100.0 + k);
    CHECK(r.data(k, 2) == Approx(1e-3 * (2.0 - 0.01 * k)).epsilon(1e-12));
  }
}

TEST_CASE("MATLAB .mat: integer counts with a sampling interval, and --rate-hz and --unit apply") {
  const Record r = read_record(mat_dir + "counts.mat");
  REQUIRE(r.channels == std::vector<std::string>{"strain_ue"});
  REQUIRE(r.fs_hz == Approx(500.0).epsilon(1e-12));
  CHECK(r.data(0, 0) == -20.0);
  CHECK(r.data(49, 0) == 29.0);
  ReadOptions o;
  o.fs_hz = 1000.0;
  o.units = {{"strain_ue", "mm"}};
  const Record s = read_record(mat_dir + "counts.mat", o);
  CHECK(s.fs_hz == 1000.0);
  CHECK(s.channels == std::vector<std::string>{"strain_m"});
  CHECK(s.data(49, 0) == Approx(0.029));
}

TEST_CASE("MATLAB .mat: files without a record are refused, naming the file") {
  CHECK(mat_error_of(mat_dir + "text.mat").find("text.mat: no numeric variable of 2 samples or more") != std::string::npos);
  vt::ScratchDir d("mat");
  CHECK(mat_error_of(d.write("fake.mat", "t_s,a_mps2\n0,1\n")).find("fake.mat: not a MATLAB .mat file") != std::string::npos);
  CHECK(mat_error_of((d.p / "none.mat").string()).find("cannot open record") != std::string::npos);
  ReadOptions o;
  o.time_column = "nothere";
  CHECK(mat_error_of(mat_dir + "vectors.mat", o).find("nothere") != std::string::npos);
}

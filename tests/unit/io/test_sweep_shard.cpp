// Shards of a sweep on disk: shard.toml read back to the last bit, ranges that cover the cases
// once, and the merged governing cases those of the whole envelope (the first of equal values
// in case order, a later shard's only when larger).
#include <unistd.h>
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "viaduct/core/error.hpp"
#include "viaduct/io/sweep_shard.hpp"

namespace sweep_shard_test {

using namespace viaduct;
namespace fs = std::filesystem;

struct Dirs {
  fs::path root;
  Dirs() {
    static int n = 0;
    root = fs::temp_directory_path() / ("viaduct-sweep-shard-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
    fs::create_directories(root);
  }
  ~Dirs() { fs::remove_all(root); }
  std::string sub(const std::string& name) const {
    fs::create_directories(root / name);
    return (root / name).string();
  }
};

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Shard k of n holding `rows` (one station per row), its files written as a shard writes them.
io::SweepShard shard_of(const std::string& dir, int k, int n, std::size_t begin, const std::vector<study::EnvelopeRow>& rows) {
  io::SweepShard s;
  s.dir = dir;
  s.k = k;
  s.n = n;
  s.begin = begin;
  s.end = begin + rows.size();
  s.n_total = 6;
  s.fingerprint = "f";
  s.files = {"envelope.csv", "failures.csv"};
  s.n_rows = rows.size();
  s.governing = study::governing(rows);
  std::ofstream(dir + "/envelope.csv") << "train,station\n" << (rows.empty() ? "" : rows.front().train + ",x\n");
  std::ofstream(dir + "/failures.csv") << "variant,train,speed_kmh,error\n";
  io::write_sweep_shard_toml(s);
  return s;
}

TEST_CASE("sweep shards: ranges cover every case once, sizes within one") {
  for (std::size_t total : {0, 1, 5, 80, 1001})
    for (int n : {1, 2, 7, 13}) {
      std::size_t next = 0;
      for (int k = 1; k <= n; ++k) {
        const auto [b, e] = io::sweep_shard_range(k, n, total);
        REQUIRE(b == next);
        REQUIRE(e - b <= total / std::size_t(n) + 1);
        next = e;
      }
      REQUIRE(next == total);
    }
}

TEST_CASE("sweep shards: shard.toml reads back to the last bit and the merged governing cases are the envelope's") {
  Dirs d;
  const double third = 1.0 / 3.0;  // 0.3333333333 in governing.csv: only shard.toml keeps it whole
  // Station "mid": its maximum 2/3 first in shard 1 and again (a tie) in shard 3, which must not
  // win; station "q": largest in shard 2 by one ulp.
  const std::vector<study::EnvelopeRow> a = {{"v", "t1", "mid", 10.0, 2 * third, third}, {"v", "t1", "q", 10.0, third, third}},
                                        b = {{"v", "t2", "mid", 20.0, third, third},
                                             {"v", "t2", "q", 20.0, std::nextafter(third, 1.0), 0.5}},
                                        c = {{"v", "t3", "mid", 30.0, 2 * third, 0.25}, {"v", "t3", "q", 30.0, 0.0, 0.5}};
  const auto s1 = shard_of(d.sub("1"), 1, 3, 0, a), s2 = shard_of(d.sub("2"), 2, 3, 2, b), s3 = shard_of(d.sub("3"), 3, 3, 4, c);
  const io::SweepShard back = io::read_sweep_shard_toml(s2.dir);
  REQUIRE(io::shard_kind(s2.dir) == "sweep");
  REQUIRE(back.governing.size() == 2);
  CHECK(back.governing[1].acc.value == std::nextafter(third, 1.0));  // bitwise
  CHECK(back.governing[1].acc.speed == 20.0);
  CHECK(back.governing[1].acc.train == "t2");
  CHECK(back.files == s2.files);
  CHECK(back.end == 4);

  const std::string out = d.sub("merged");
  const io::SweepMerge m = io::merge_sweep_shards({s3.dir, s1.dir, s2.dir}, out);  // any order
  std::vector<study::EnvelopeRow> all = a;
  all.insert(all.end(), b.begin(), b.end());
  all.insert(all.end(), c.begin(), c.end());
  const auto whole = study::governing(all);
  REQUIRE(m.governing.size() == whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    CHECK(m.governing[i].station == whole[i].station);
    CHECK(m.governing[i].acc.train == whole[i].acc.train);
    CHECK(m.governing[i].acc.value == whole[i].acc.value);
    CHECK(m.governing[i].disp.train == whole[i].disp.train);
  }
  CHECK(m.governing[0].acc.train == "t1");  // the tie: the first in case order
  CHECK(m.governing[1].acc.train == "t2");
  CHECK(m.governing[1].disp.train == "t2");  // 0.5 in shards 2 and 3: shard 2's
  CHECK(read(out + "/envelope.csv") == "train,station\nt1,x\nt2,x\nt3,x\n");

  // A foreign shard, a gap.
  io::SweepShard foreign = s2;
  foreign.fingerprint = "g";
  io::write_sweep_shard_toml(foreign);
  REQUIRE_THROWS_WITH(io::merge_sweep_shards({s1.dir, s2.dir, s3.dir}, out), Catch::Contains("is of another study than"));
  REQUIRE_THROWS_WITH(io::merge_sweep_shards({s1.dir, s3.dir}, out), Catch::Contains("shard 2/3 is missing"));
  // A governing case without its station (a hand's edit) is an input error naming the key.
  {
    std::string text = read(s3.dir + "/shard.toml");
    const auto at = text.find("\nstation = ");
    REQUIRE(at != std::string::npos);
    text.replace(at, 11, "\nstatio = ");
    std::ofstream(s3.dir + "/shard.toml") << text;
  }
  REQUIRE_THROWS_WITH(io::read_sweep_shard_toml(s3.dir), Catch::Contains("key 'governing.station': missing or of the wrong type"));
}

}  // namespace sweep_shard_test

// Sampled studies on disk: the study from the scenario, variants per sample, streaming and
// resuming, statistics files, shards and their merge.
#include "viaduct/io/sampled.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <unistd.h>

#include <toml.hpp>

#include "atomic_file.hpp"
#include "csv_cells.hpp"
#include "flat_items.hpp"
#include "toml_file.hpp"
#include "viaduct/io/results.hpp"

namespace viaduct::io {

namespace fs = std::filesystem;

namespace sampled_detail {

using detail::AtomicFile;
using detail::csv_text;

[[noreturn]] void bad(const Value& v, const std::string& why) { throw InputError(v.where, why); }

std::string num(double x) { return format_number(x, 12); }

// The distribution of item `pre` ("sweep.variants[0].").
study::Distribution distribution_of(const FlatScenario& flat, const std::string& pre) {
  if (!flat.has(pre + "distribution"))
    bad(flat.at(pre + "key"), "a sampled study needs the distribution of each key's factor (" + pre +
                                  "distribution = \"uniform\", \"normal\", \"lognormal\" or \"truncated\")");
  const Value& kind = flat.at(pre + "distribution");
  study::Distribution d;
  if (!study::distribution_kind_of(kind.s, &d.kind)) bad(kind, "unknown distribution '" + kind.s + "'");
  std::vector<std::string> need;
  switch (d.kind) {
    case study::DistributionKind::uniform: need = {"low", "high"}; break;
    case study::DistributionKind::normal:
    case study::DistributionKind::lognormal: need = {"mean", "sd"}; break;
    case study::DistributionKind::truncated: need = {"mean", "sd", "low", "high"}; break;
  }
  for (const char* p : {"low", "high", "mean", "sd"}) {
    const bool wanted = std::find(need.begin(), need.end(), p) != need.end();
    if (wanted && !flat.has(pre + p))
      bad(kind, "a " + kind.s + " factor needs " + [&] {
        std::string s;
        for (const auto& n : need) s += (s.empty() ? "" : ", ") + n;
        return s;
      }() + " (missing: " + p + ")");
    if (!wanted && flat.has(pre + p)) bad(flat.at(pre + p), "a " + kind.s + " factor takes no " + std::string(p));
  }
  if (flat.has(pre + "low")) d.low = flat.at(pre + "low").x;
  if (flat.has(pre + "high")) d.high = flat.at(pre + "high").x;
  if (flat.has(pre + "mean")) d.mean = flat.at(pre + "mean").x;
  if (flat.has(pre + "sd")) d.sd = flat.at(pre + "sd").x;
  std::string why;
  if (!d.is_valid(&why)) {
    // The message starts with the field it is about when there is one.
    for (const char* p : {"low", "high", "mean", "sd"})
      if (why.rfind(std::string(p) + " =", 0) == 0 && flat.has(pre + p)) bad(flat.at(pre + p), why);
    bad(kind, why);
  }
  return d;
}

// Checks that the key can be varied by factors from `d`: numeric, its reference not 0, its rule
// kept at both ends of the support.
void check_key_range(const FlatScenario& flat, const std::string& key, const study::Distribution& d, const Value& where) {
  if (!flat.has(key)) bad(where, "'" + key + "' is not a key of this scenario");
  const Value& v = flat.at(key);
  const bool zero = (v.type == ValueType::number && v.x == 0.0) ||
                    (v.type == ValueType::number_list && std::all_of(v.xs.begin(), v.xs.end(), [](double x) { return x == 0.0; }));
  if (zero)
    bad(where, "the reference value of " + key + " is 0 (" + v.where.file + ":" + std::to_string(v.where.line) +
                   "): a factor cannot vary it; give the key a non-zero value");
  const auto [lo, hi] = d.support();
  for (double f : {lo, hi}) {
    FlatScenario copy = flat;
    scale_key(copy, key, f, where.where);
  }
}

Matrix correlations_of(const FlatScenario& flat, const std::vector<std::string>& keys, const std::vector<std::string>& labels) {
  const auto items = detail::item_indices(flat, "sweep.correlations");
  if (items.empty()) return Matrix();
  Matrix r = Matrix::Identity(Index(keys.size()), Index(keys.size()));
  for (std::size_t i : items) {
    const std::string pre = "sweep.correlations[" + std::to_string(i) + "].";
    const Value& k = flat.at(pre + "keys");
    const Value& rho = flat.at(pre + "rho");
    if (k.ss.size() != 2) bad(k, "needs two keys (or labels) of sweep.variants");
    Index idx[2];
    for (int j = 0; j < 2; ++j) {
      std::size_t a = 0;
      while (a < keys.size() && keys[a] != k.ss[std::size_t(j)] && labels[a] != k.ss[std::size_t(j)]) ++a;
      if (a == keys.size()) bad(k, "'" + k.ss[std::size_t(j)] + "' is not a key or label of sweep.variants");
      idx[j] = Index(a);
    }
    if (idx[0] == idx[1]) bad(k, "a key's correlation with itself is 1");
    if (!(rho.x >= -1.0 && rho.x <= 1.0)) bad(rho, "must be in [-1, 1], got " + num(rho.x));
    if (r(idx[0], idx[1]) != 0.0) bad(k, "this pair is correlated twice");
    r(idx[0], idx[1]) = r(idx[1], idx[0]) = rho.x;
  }
  return r;
}

}  // namespace sampled_detail

using sampled_detail::AtomicFile;
using sampled_detail::csv_text;

study::SampleDesign SampledStudy::layout() const {
  study::SampleDesign l;
  l.d = int(keys.size());
  l.n_base = spec.n;
  l.saltelli = spec.sensitivity;
  return l;
}

Index SampledStudy::n_total() const { return spec.sensitivity ? spec.n * (Index(keys.size()) + 2) : spec.n; }

bool is_sampled(const FlatScenario& flat) { return flat.has("sweep.mode") && flat.at("sweep.mode").s == "sample"; }

SampledStudy sampled_study(const FlatScenario& flat) {
  namespace sd = sampled_detail;
  SampledStudy st;
  const Value& mode = flat.at("sweep.mode");
  const auto items = detail::item_indices(flat, "sweep.variants");
  if (items.empty()) sd::bad(mode, "a sampled study needs [[sweep.variants]] entries with a key and its distribution");
  for (std::size_t i : items) {
    const std::string pre = "sweep.variants[" + std::to_string(i) + "].";
    const Value& key = flat.at(pre + "key");
    if (flat.has(pre + "factors"))
      sd::bad(flat.at(pre + "factors"), "factors list the values of one-at-a-time and grid sweeps; a sampled study draws each "
                                    "key's factor from its distribution (distribution, low, high, mean, sd)");
    if (std::find(st.keys.begin(), st.keys.end(), key.s) != st.keys.end()) sd::bad(key, "'" + key.s + "' is sampled twice");
    const study::Distribution d = sd::distribution_of(flat, pre);
    sd::check_key_range(flat, key.s, d, key);
    st.keys.push_back(key.s);
    st.labels.push_back(flat.at(pre + "label").s.empty() ? key.s : flat.at(pre + "label").s);
    st.spec.distributions.push_back(d);
  }
  if (!flat.has("sweep.n_samples")) sd::bad(mode, "a sampled study needs sweep.n_samples");
  const Value& n = flat.at("sweep.n_samples");
  if (n.x < 2) sd::bad(n, "must be >= 2 for a sampled study, got " + sd::num(n.x));
  if (n.x > 1e8) sd::bad(n, "must be <= 1e8, got " + sd::num(n.x));
  st.spec.n = Index(n.x);
  study::sampling_method_of(flat.at("sweep.sampling").s, &st.spec.method);
  st.spec.seed = std::uint64_t(flat.at("sweep.seed").x);
  st.spec.sensitivity = flat.at("sweep.sensitivity").b;
  st.spec.correlation = sd::correlations_of(flat, st.keys, st.labels);
  if (st.spec.sensitivity && st.spec.correlation.size() > 0)
    sd::bad(flat.at("sweep.sensitivity"), "Sobol indices assume independent inputs: remove [[sweep.correlations]] or the sensitivity");
  const int width = int(st.keys.size()) * (st.spec.sensitivity ? 2 : 1);
  if (st.spec.method == study::SamplingMethod::sobol && width > study::SobolSequence::max_dimensions())
    sd::bad(flat.at("sweep.sampling"), "a Sobol sequence has at most " + std::to_string(study::SobolSequence::max_dimensions()) +
                                       " dimensions; this study needs " + std::to_string(width));
  const Value& pct = flat.at("sweep.percentiles");
  for (double p : pct.xs)
    if (!(p >= 0.0 && p <= 100.0)) sd::bad(pct, "percentiles must lie in [0, 100], got " + sd::num(p));
  st.stats.percentiles = pct.xs;
  st.stats.acc_limit = flat.at("sweep.acceleration_limit_mps2").x;
  st.stats.sobol.n_bootstrap = int(std::min(1e6, flat.at("sweep.n_bootstrap").x));
  st.stats.sobol.seed = st.spec.seed;
  st.batch = Index(std::min(1e6, flat.at("sweep.batch").x));
  st.fingerprint = sha256_hex(resolved_toml(flat));
  return st;
}

study::Variant sample_variant(const FlatScenario& flat, const SampledStudy& st, const study::SampleDesign& design, Index s,
                              const study::Scenario& reference) {
  study::Variant v;
  v.label = std::to_string(s);
  FlatScenario f = flat;
  for (std::size_t j = 0; j < st.keys.size(); ++j) v.factors.emplace_back(st.keys[j], design.factors(s, Index(j)));
  try {
    for (std::size_t j = 0; j < st.keys.size(); ++j)
      scale_key(f, st.keys[j], design.factors(s, Index(j)), f.at(st.keys[j]).where);
    v.scenario = to_scenario(f);
  } catch (const InputError& e) {
    v.scenario = reference;
    v.error = "sample " + v.label + ": " + e.what();
  }
  return v;
}

void write_samples_csv(const std::string& path, const SampledStudy& st, const study::SampleDesign& design, Index begin,
                       Index end) {
  AtomicFile f(path);
  std::fprintf(f.get(), "sample,block");
  for (const auto& k : st.keys) std::fprintf(f.get(), ",%s", csv_text(k + "_factor").c_str());
  std::fprintf(f.get(), "\n");
  for (Index s = begin; s < end; ++s) {
    const int b = design.block(s);
    const std::string block = !design.saltelli ? "sample" : b == 0 ? "A" : b == 1 ? "B" : "AB_" + st.labels[std::size_t(b - 2)];
    std::fprintf(f.get(), "%lld,%s", static_cast<long long>(s), csv_text(block).c_str());
    for (Index j = 0; j < design.factors.cols(); ++j) std::fprintf(f.get(), ",%.10g", design.factors(s, j));
    std::fprintf(f.get(), "\n");
  }
  f.commit();
}

}  // namespace viaduct::io

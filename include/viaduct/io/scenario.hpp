#pragma once
/// \file Scenario files (TOML) → study::Scenario.
///
/// A scenario is read into a flat map of dotted keys ("track.pad.k", "stations[0].at"): the
/// scenario file, the component files it references (`bridge.file`, `track.file`, paths
/// relative to the referencing file) and `--set key=value` overrides, with precedence
/// override > scenario > component. Every key is declared in scenario_schema() with type,
/// default, unit, constraint and a one-line doc; unknown keys are errors with file:line and a
/// "did you mean". Only sections the scenario names are filled with defaults.

#include <map>
#include <set>
#include <string>
#include <vector>

#include "viaduct/core/error.hpp"
#include "viaduct/study/scenario.hpp"

namespace viaduct::solve {
struct MethodTraits;
}

namespace viaduct::io {

enum class ValueType { boolean, integer, number, string, number_list, string_list, number_or_list };

/// One scenario value with where it came from.
struct Value {
  ValueType type = ValueType::number;  ///< as stored (integer, number, … ; never number_or_list)
  bool b = false;
  double x = 0.0;                      ///< number and integer
  std::string s;
  std::vector<double> xs;
  std::vector<std::string> ss;
  SourceLocation where;                ///< file and line; file "--set" for overrides, "default"
  std::string to_toml() const;         ///< TOML literal
};

/// Sets the field of a scenario that a key declares (values already checked against the key's
/// type and constraint).
using KeySetter = void (*)(study::Scenario&, const Value&);
/// The field a number or boolean key sets, read from a scenario (booleans as 0/1; a track key from
/// model::TrackParams{}): what a test compares with the key's default.
using KeyGetter = double (*)(const study::Scenario&);
/// The same for a string key (an enumeration's value by its name).
using KeyTextGetter = std::string (*)(const study::Scenario&);

/// Declaration of one key. "[]" in a key stands for an array index ("stations[].name").
struct KeySpec {
  std::string key;
  ValueType type;
  std::string default_toml;  ///< TOML literal; empty: no default
  std::string unit;          ///< SI unit, "-" for dimensionless, "" for text
  std::string constraint;    ///< "> 0", ">= 0", "[0, 1)", "[0, 1]", "(0, 1]", ">= 1", "a|b|c", or ""
  std::string doc;           ///< one line; "(required)" marks a key without default that must be given
  /// The study::Scenario field the key sets; null for keys read by hand (several keys to one
  /// field, arrays, files) or not read into the scenario (notes, fit sections).
  KeySetter set = nullptr;
  /// With `set` for a number or boolean key: the field it sets (the struct's default on a
  /// default-constructed scenario equals default_toml: tests/unit/io/test_scenario.cpp).
  KeyGetter get = nullptr;
  KeyTextGetter get_text = nullptr;  ///< with `set` for a string key: the same as `get`
  bool required() const { return doc.find("(required)") != std::string::npos; }
};
const std::vector<KeySpec>& scenario_schema();

/// Flat resolved view of a scenario.
struct FlatScenario {
  std::string path;                      ///< the scenario file
  std::map<std::string, Value> values;   ///< every key, defaults included
  std::set<std::string> defaulted;       ///< keys whose value is the schema default
  /// Value of key or throw InputError naming it.
  const Value& at(const std::string& key) const;
  bool has(const std::string& key) const { return values.count(key) > 0; }
};

/// Reads, merges, overrides ("key=value", value in TOML syntax; bare words are strings), removes
/// the `unset` keys (a key, or a table or array of tables with everything under it: "sweep.variants"),
/// checks types, constraints and unknown keys, fills defaults. An empty `path` reads no file:
/// every key comes from the overrides (relative paths then from the working directory). Throws
/// InputError.
FlatScenario load_flat(const std::string& path, const std::vector<std::string>& overrides = {},
                       const std::vector<std::string>& unset = {});
/// The defaults that follow from other keys, recomputed from the values now in `flat` (load_flat
/// calls it; call it again after changing such a key): analysis.beta and analysis.gamma not given
/// take HHT-α's own, (1 − α)²/4 and (1 − 2α)/2 (0.25 and 0.5 at α = 0).
void derive_defaults(FlatScenario& flat);
/// Converts to plain data, checking cross-key rules (required keys, physics). Throws InputError
/// with the key and where it was set.
study::Scenario to_scenario(const FlatScenario& flat);
/// Refuses, at the key that chose it (`method_key`: analysis.method), a method this build lacks
/// (traits.built false: IDA without SUNDIALS, CMake VIADUCT_IDA=OFF); to_scenario() calls it with
/// solve::method_traits() of the method the scenario resolves to.
void require_method_built(const Value& method_key, const solve::MethodTraits& traits);
/// The sweep's variants (one-at-a-time multipliers or a full grid) as resolved scenarios;
/// a single "reference" variant without [[sweep.variants]].
/// A variant that cannot be formed (a factor breaking its key's rule) is an InputError, or with
/// isolate_failures a Variant whose `error` says why (the sweep fails its cases and runs the rest).
std::vector<study::Variant> sweep_variants(const FlatScenario& flat, bool isolate_failures = false);
/// Multiplies a numeric key (number or list) by `factor` in place; InputError at `declared` (the
/// variant's entry) if the key is absent or not numeric.
void scale_key(FlatScenario& flat, const std::string& key, double factor, const SourceLocation& declared);

/// Sets a numeric key (a number, or a list that then holds `value` alone) to `value`, checking
/// the key's constraint; InputError naming the key and the violated constraint.
void set_number(FlatScenario& flat, const std::string& key, double value);
/// Declaration of a key ("stations[2].at" finds "stations[].at"); nullptr when unknown.
const KeySpec* find_key_spec(const std::string& key);
/// Human-readable resolved scenario: key = value  # unit, origin.
std::string format_resolved(const FlatScenario& flat);
/// The resolved scenario as TOML (quoted dotted keys), for manifests.
std::string resolved_toml(const FlatScenario& flat);
/// Markdown table of the schema (docs/scenarios.md is generated from it).
std::string schema_markdown();

/// True when `key` is `prefix` or lies under it (a table's key or an array's item):
/// sweep.variants[0].key is under sweep.variants and under sweep, not under swee.
inline bool key_is_under(const std::string& key, const std::string& prefix) {
  return key == prefix || (key.size() > prefix.size() && key.compare(0, prefix.size(), prefix) == 0 &&
                           (key[prefix.size()] == '.' || key[prefix.size()] == '['));
}

/// True for an entry of train.files that names built-in trains ("hslm:A1-A10"), not a file.
inline bool is_builtin_train(const std::string& entry) { return entry.rfind("hslm:", 0) == 0; }

/// Reads a train file: TOML (kind = "hslm" | "regular" | "axles") or CSV with columns
/// position_m,load_kN ('#' comment lines). Throws InputError with file and line.
load::Train read_train_file(const std::string& path);
/// The coach file a train file of kind "coaches" names (its `vehicle`, resolved beside the train
/// file), for manifests; empty for any other train file or one that does not read.
std::string coach_file_of(const std::string& train_path);
/// A coach file (data/vehicles/*.toml, kind = "coach"): masses, inertias, geometry and
/// suspensions of load::CoachSpec with their units in the key names. InputError with file, line
/// and key for a missing, unknown or invalid key (the violated constraint named).
load::CoachSpec read_coach_file(const std::string& path);

}  // namespace viaduct::io

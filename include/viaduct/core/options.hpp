#pragma once
/// \file One way for options structs to explain a rejected value (DESIGN.md §3.2, after Ceres'
/// OPTION_GE): "NewmarkOptions::gamma = 0.3: violated constraint gamma >= 0.5 (…)", naming the
/// struct, the field, the value and the rule.
///
///   bool NewmarkOptions::is_valid(std::string* why) const {
///     OptionsCheck c("NewmarkOptions", why);
///     return c.require(beta > 0.0, "beta", beta, "beta > 0") && …;
///   }
///
/// A non-finite value fails require(), whatever the condition says; require_or_infinite() lets
/// ±infinity through for fields where it means "no limit".

#include <cmath>
#include <string>

#include "viaduct/core/error.hpp"

namespace viaduct {

class OptionsCheck {
 public:
  /// `type`: the struct's name as it appears in messages; `why` may be null.
  OptionsCheck(const char* type, std::string* why) : type_(type), why_(why) {}

  /// True when `ok` holds and `value` is finite; otherwise writes the message and returns false.
  bool require(bool ok, const char* field, double value, const std::string& rule) {
    if (ok && std::isfinite(value)) return true;
    return fail(field, format_number(value, 6), rule);
  }
  /// The same for a field where ±infinity means "no limit": only NaN fails besides `ok`.
  bool require_or_infinite(bool ok, const char* field, double value, const std::string& rule) {
    if (ok && !std::isnan(value)) return true;
    return fail(field, format_number(value, 6), rule);
  }
  /// For a non-numeric field (or one whose value is shown otherwise): writes the message, false.
  bool fail(const char* field, const std::string& value, const std::string& rule) {
    if (why_) *why_ = std::string(type_) + "::" + field + " = " + value + ": violated constraint " + rule;
    return false;
  }

 private:
  const char* type_;
  std::string* why_;
};

/// Throws InputError("<context>: <why>") when `options.is_valid` fails.
template <class Options>
void require_valid(const Options& options, const char* context) {
  std::string why;
  if (!options.is_valid(&why)) throw InputError(std::string(context) + ": " + why);
}

}  // namespace viaduct

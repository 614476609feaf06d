// The one table of match settings: name, member, default, range and help of each field.
// The CLI flags, the API codec, the job journal and report JSON, validation and the
// preprocessing cache key all walk this table, so a new setting is one row here (plus its
// member in match_settings.h and, unless it is local, its field in the .proto; a test
// checks the table against the proto descriptor).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "isocorr/settings/match_settings.h"

namespace isocorr {

enum class SettingType { kInt, kDouble, kBool, kChoice };

enum class SettingScope {
  kMatch,       // read by the match itself
  kPreprocess,  // read by per-mesh preprocessing: part of the shape cache key
  kLocal,       // how this process runs (threads): not sent to a server, not in the key
};

struct SettingRange {
  double min = 0, max = 0;
  bool min_open = false, max_open = false;  // open ends exclude the bound itself
  bool contains(double value) const;
  std::string describe() const;  // "[0, 1)"
};

struct SettingField {
  std::string_view name;  // snake_case: the proto field, the JSON key; the flag is --name-with-dashes
  std::string_view help;
  SettingType type = SettingType::kInt;
  SettingScope scope = SettingScope::kMatch;
  SettingRange range;                   // numeric types; a choice's range is its index range
  std::vector<std::string_view> choices;  // kChoice: the names, in the enum's order

  // Every value seen as a number: ints and doubles as they are, bools 0/1, a choice its
  // index. Exact for every member type.
  std::function<double(const MatchSettings&)> get;
  std::function<void(MatchSettings&, double)> set;

  std::string flag() const;  // "--level0-radius"
  // The value as text that parses back to the same value: an int, the shortest exact
  // text of a double, "true"/"false", a choice's name.
  std::string format(const MatchSettings& settings) const;
  // Parses what format() writes (also 1/0/yes/no for bools); throws InputError naming the
  // field on malformed text. Does not check the range (validate does).
  void parse(MatchSettings& settings, const std::string& text) const;
  // Throws InputError naming the field when its value lies outside the range.
  void check(const MatchSettings& settings) const;
};

// Every field, in a fixed order (the order of --help and of JSON objects).
const std::vector<SettingField>& settings_schema();
const SettingField* find_setting(std::string_view name);

// Exact text of the fields of one scope: equal keys mean equal values.
std::string settings_key(const MatchSettings& settings, SettingScope scope);

// Throws InputError naming the first preprocessing field out of range.
void validate_preprocess_options(const PreprocessOptions& options);

// True when every field of the table has the same value in both, and the same landmarks.
bool same_settings(const MatchSettings& a, const MatchSettings& b);

}  // namespace isocorr

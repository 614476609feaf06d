// The settings table: every field round-trips through text and JSON, ranges are checked
// and named, and the cache key is exact.
#include "isocorr/settings/settings_schema.h"

#include <gtest/gtest.h>

#include <set>

#include "isocorr/settings/settings_json.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

// A valid value other than the default for every field.
MatchSettings all_changed() {
  MatchSettings s;
  for (const SettingField& field : settings_schema()) {
    const MatchSettings defaults;
    const double old = field.get(defaults);
    double value = old;
    switch (field.type) {
      case SettingType::kBool: value = old != 0 ? 0 : 1; break;
      case SettingType::kChoice: value = old == 0 ? 1 : 0; break;
      case SettingType::kInt: value = old + 1 <= field.range.max ? old + 1 : old - 1; break;
      case SettingType::kDouble: value = old * 0.9 + field.range.min * 0.1 + 1e-7; break;
    }
    field.set(s, value);
  }
  s.max_tracked = s.min_tracked + 5;  // keep the cross-field rules
  s.level0_samples = 5;
  return s;
}

TEST(SettingsSchema, NamesAreUniqueAndFlagsFollowThem) {
  std::set<std::string_view> names;
  for (const SettingField& field : settings_schema()) {
    EXPECT_TRUE(names.insert(field.name).second) << field.name;
    EXPECT_FALSE(field.help.empty()) << field.name;
    EXPECT_EQ(find_setting(field.name), &field);
  }
  EXPECT_EQ(find_setting("level0_radius")->flag(), "--level0-radius");
  EXPECT_GE(settings_schema().size(), 30u);
}

TEST(SettingsSchema, DefaultsAreValidAndEveryFieldChanges) {
  const MatchSettings defaults;
  EXPECT_NO_THROW(defaults.validate());
  const MatchSettings changed = all_changed();
  EXPECT_NO_THROW(changed.validate());
  for (const SettingField& field : settings_schema())
    EXPECT_NE(field.get(changed), field.get(defaults)) << field.name << ": the table's accessor reaches no member";
}

TEST(SettingsSchema, TextRoundTripIsExact) {
  const MatchSettings changed = all_changed();
  MatchSettings back;
  for (const SettingField& field : settings_schema()) field.parse(back, field.format(changed));
  EXPECT_TRUE(same_settings(back, changed));
  MatchSettings s;
  EXPECT_THROW(find_setting("level0_radius")->parse(s, "0.2x"), InputError);
  EXPECT_THROW(find_setting("min_tracked")->parse(s, "1.5"), InputError);
  EXPECT_THROW(find_setting("selection")->parse(s, "best"), InputError);
  EXPECT_THROW(find_setting("handedness_guard")->parse(s, "maybe"), InputError);
}

TEST(SettingsSchema, JsonRoundTripIsExactAndOldRecordsKeepDefaults) {
  const MatchSettings changed = all_changed();
  EXPECT_TRUE(same_settings(settings_from_json(settings_to_json(changed)), changed));
  const nlohmann::json old_record = {{"level0_radius", 0.25}, {"selection", "least-diso"}, {"retired_field", 3}};
  const MatchSettings back = settings_from_json(old_record);
  EXPECT_DOUBLE_EQ(back.preprocess.level0_radius, 0.25);
  EXPECT_EQ(back.selection, SelectionRule::kLeastDistortion);
  EXPECT_EQ(back.min_tracked, MatchSettings{}.min_tracked);
  EXPECT_THROW(settings_from_json({{"min_tracked", "many"}}), InputError);
}

// Found by fuzz/settings_json_fuzzer.cpp: an integer wider than 32 bits was converted to
// the int member (undefined behaviour; UBSan stops the sanitizer build's run on it).
TEST(SettingsSchema, JsonIntegersBeyond32BitsAreRejected) {
  for (const char* bytes : {R"({"max_tracked": 99999999999})", R"({"min_tracked": -2147483649})",
                            R"({"max_level0_maps": 18446744073709551615})"})
    EXPECT_THROW(settings_from_json(nlohmann::json::parse(bytes)), InputError) << bytes;
  EXPECT_EQ(settings_from_json(nlohmann::json::parse(R"({"max_tracked": 2147483647})")).max_tracked, 2147483647);
}

TEST(SettingsSchema, ValidationNamesTheFieldOutOfRange) {
  for (const SettingField& field : settings_schema()) {
    if (field.type == SettingType::kBool || field.type == SettingType::kChoice) continue;
    MatchSettings s;
    field.set(s, field.range.min_open ? field.range.min : field.range.min - 1);
    try {
      s.validate();
      ADD_FAILURE() << field.name << " accepted a value below its range";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field.name), std::string::npos) << e.what();
    }
  }
  MatchSettings s;
  s.preprocess.level0_radius = 5;
  EXPECT_THROW(s.validate(), InputError);
  EXPECT_THROW(validate_preprocess_options(s.preprocess), InputError);
}

TEST(SettingsSchema, CacheKeyIsExactAndCoversOnlyPreprocessing) {
  MatchSettings a, b;
  b.preprocess.level0_radius = 0.2000001;
  EXPECT_NE(a.preprocess.key(), b.preprocess.key());
  b = a;
  b.preprocess.cleaning.repair_non_manifold_edges = false;
  EXPECT_NE(a.preprocess.key(), b.preprocess.key());
  b = a;
  b.min_tracked = 7;
  b.threads = 1;
  EXPECT_EQ(a.preprocess.key(), b.preprocess.key());
  EXPECT_EQ(a.preprocess.key(), settings_key(a, SettingScope::kPreprocess));
}

}  // namespace
}  // namespace isocorr

// The engine's settings table against the API's MatchSettings message: the same fields
// with the same types, so a setting added on one side only fails here.
#include "codec/settings_codec.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>

#include "codec/result_part_codec.h"
#include "isocorr/settings/settings_schema.h"

namespace isocorr::api {
namespace {

using google::protobuf::FieldDescriptor;

FieldDescriptor::CppType cpp_type_of(SettingType type) {
  switch (type) {
    case SettingType::kInt: return FieldDescriptor::CPPTYPE_INT32;
    case SettingType::kDouble: return FieldDescriptor::CPPTYPE_DOUBLE;
    case SettingType::kBool: return FieldDescriptor::CPPTYPE_BOOL;
    case SettingType::kChoice: return FieldDescriptor::CPPTYPE_ENUM;
  }
  return FieldDescriptor::CPPTYPE_STRING;
}

TEST(SettingsCodec, TableAndProtoHaveTheSameFields) {
  const auto* descriptor = v1::MatchSettings::descriptor();
  for (const SettingField& field : settings_schema()) {
    const FieldDescriptor* fd = descriptor->FindFieldByName(std::string(field.name));
    if (field.scope == SettingScope::kLocal) {
      EXPECT_EQ(fd, nullptr) << field.name << " is local to a process and must not be in the API";
      continue;
    }
    ASSERT_NE(fd, nullptr) << "setting " << field.name << " has no field in isocorr.v1.MatchSettings";
    EXPECT_EQ(fd->cpp_type(), cpp_type_of(field.type)) << field.name;
    if (field.type == SettingType::kChoice)
      EXPECT_EQ(fd->enum_type()->value_count(), static_cast<int>(field.choices.size()) + 1) << field.name;
    else
      EXPECT_TRUE(fd->has_presence()) << field.name << " must be `optional` so that unset means default";
  }
  for (int i = 0; i < descriptor->field_count(); ++i) {
    // The landmarks are a list, handled beside the table (settings_schema.cpp).
    if (descriptor->field(i)->name() == "landmarks") {
      EXPECT_TRUE(descriptor->field(i)->is_repeated());
      continue;
    }
    const SettingField* field = find_setting(descriptor->field(i)->name());
    EXPECT_NE(field, nullptr) << "proto field " << descriptor->field(i)->name() << " is not in the settings table";
  }
}

TEST(SettingsCodec, LandmarksRoundTripInOrder) {
  MatchSettings settings;
  settings.landmarks = {{12, 40}, {7, 9}, {0, 3}};
  const v1::MatchSettings proto = settings_to_proto(settings);
  ASSERT_EQ(proto.landmarks_size(), 3);
  EXPECT_EQ(proto.landmarks(1).source_vertex(), 7);
  EXPECT_EQ(proto.landmarks(1).target_vertex(), 9);
  EXPECT_EQ(settings_from_proto(proto).landmarks, settings.landmarks);
  EXPECT_TRUE(same_settings(settings_from_proto(proto), settings));
  EXPECT_TRUE(settings_from_proto(v1::MatchSettings()).landmarks.empty());
}

TEST(SettingsCodec, UnsetFieldsKeepDefaultsAndEverySetFieldRoundTrips) {
  EXPECT_TRUE(same_settings(settings_from_proto(v1::MatchSettings()), MatchSettings{}));
  MatchSettings changed;
  changed.preprocess.level0_radius = 0.2000001;
  changed.selection = SelectionRule::kLeastDistortion;
  changed.tracking.pool_all_levels = false;
  changed.preprocess.cleaning.repair_non_manifold_edges = false;
  changed.dense.anchor_refinement_rounds = 3;
  EXPECT_TRUE(same_settings(settings_from_proto(settings_to_proto(changed)), changed));

  v1::MatchSettings unknown_choice;
  unknown_choice.set_selection(static_cast<v1::MatchSettings::Selection>(7));
  EXPECT_THROW(settings_from_proto(unknown_choice), InputError);
}

TEST(ResultPartCodec, ApiPartsAreTheEnginePartsInOrder) {
  const auto* parts = v1::ResultPart_descriptor();
  ASSERT_EQ(parts->value_count(), static_cast<int>(kAllResultParts.size()) + 1);
  for (const ResultPart part : kAllResultParts) {
    std::string proto_name = v1::ResultPart_Name(result_part_to_proto(part));
    std::transform(proto_name.begin(), proto_name.end(), proto_name.begin(), [](unsigned char c) { return std::tolower(c); });
    // FORWARD_MAP -> forward, REPORT_JSON -> report, FORWARD_CONFIDENCE -> forward_confidence
    for (const std::string suffix : {"_map", "_json"})
      if (proto_name.size() > suffix.size() && proto_name.ends_with(suffix)) proto_name.resize(proto_name.size() - suffix.size());
    EXPECT_EQ(proto_name, result_part_name(part));
    EXPECT_EQ(result_part_from_proto(result_part_to_proto(part)), part);
  }
  EXPECT_EQ(result_part_from_proto(0), std::nullopt);
  EXPECT_EQ(result_part_from_proto(99), std::nullopt);
}

}  // namespace
}  // namespace isocorr::api

#include "codec/settings_codec.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>

#include "isocorr/settings/settings_schema.h"
#include "isocorr/util/error.h"

namespace isocorr::api {
namespace {

using google::protobuf::FieldDescriptor;

// The proto field of a schema row: same name. Local rows (threads) have none.
const FieldDescriptor* proto_field(const SettingField& field) {
  if (field.scope == SettingScope::kLocal) return nullptr;
  return v1::MatchSettings::descriptor()->FindFieldByName(std::string(field.name));
}

}  // namespace

// Both directions walk the engine's settings table with protobuf reflection, so a new
// setting needs no line here; tests/proto/settings_codec_test.cpp checks that the table
// and the message agree field by field. A choice's index i is enum value i + 1 (0 is
// UNSPECIFIED, the engine default).
MatchSettings settings_from_proto(const v1::MatchSettings& proto) {
  MatchSettings settings;
  const auto* reflection = proto.GetReflection();
  for (const auto& field : settings_schema()) {
    const FieldDescriptor* fd = proto_field(field);
    if (!fd) continue;
    if (fd->has_presence() && !reflection->HasField(proto, fd)) continue;
    switch (field.type) {
      case SettingType::kInt: field.set(settings, reflection->GetInt32(proto, fd)); break;
      case SettingType::kDouble: field.set(settings, reflection->GetDouble(proto, fd)); break;
      case SettingType::kBool: field.set(settings, reflection->GetBool(proto, fd) ? 1 : 0); break;
      case SettingType::kChoice: {
        const int value = reflection->GetEnumValue(proto, fd);
        if (value == 0) break;  // UNSPECIFIED
        if (value < 1 || value > static_cast<int>(field.choices.size()))
          throw InputError("setting " + std::string(field.name) + " has the unknown value " + std::to_string(value));
        field.set(settings, value - 1);
        break;
      }
    }
  }
  // Not a row of the table (settings_schema.cpp says why).
  for (const v1::Landmark& l : proto.landmarks()) settings.landmarks.push_back({l.source_vertex(), l.target_vertex()});
  return settings;
}

v1::MatchSettings settings_to_proto(const MatchSettings& settings) {
  v1::MatchSettings proto;
  const auto* reflection = proto.GetReflection();
  for (const auto& field : settings_schema()) {
    const FieldDescriptor* fd = proto_field(field);
    if (!fd) continue;
    const double value = field.get(settings);
    switch (field.type) {
      case SettingType::kInt: reflection->SetInt32(&proto, fd, static_cast<int32_t>(value)); break;
      case SettingType::kDouble: reflection->SetDouble(&proto, fd, value); break;
      case SettingType::kBool: reflection->SetBool(&proto, fd, value != 0); break;
      case SettingType::kChoice: reflection->SetEnumValue(&proto, fd, static_cast<int>(value) + 1); break;
    }
  }
  for (const Landmark& l : settings.landmarks) {
    v1::Landmark* entry = proto.add_landmarks();
    entry->set_source_vertex(l.source_vertex);
    entry->set_target_vertex(l.target_vertex);
  }
  return proto;
}

}  // namespace isocorr::api

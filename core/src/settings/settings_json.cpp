#include "isocorr/settings/settings_json.h"

#include <limits>

#include "isocorr/settings/settings_schema.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

// One entry of "landmarks": {"source_vertex": s, "target_vertex": t}, each a 32-bit integer.
Landmark landmark_from_json(const nlohmann::json& entry, size_t index) {
  const std::string name = "landmarks[" + std::to_string(index) + "]";
  if (!entry.is_object()) throw InputError(name + " is not an object with source_vertex and target_vertex");
  auto vertex = [&](const char* key) {
    const auto it = entry.find(key);
    if (it == entry.end() || !it->is_number_integer() || !(it->get<double>() >= std::numeric_limits<int>::min() &&
                                                           it->get<double>() <= std::numeric_limits<int>::max()))
      throw InputError(name + "." + key + " is missing or not an integer within 32 bits");
    return it->get<int>();
  };
  return Landmark{vertex("source_vertex"), vertex("target_vertex")};
}

}  // namespace

nlohmann::json settings_to_json(const MatchSettings& settings) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& field : settings_schema()) {
    const double value = field.get(settings);
    const std::string key(field.name);
    switch (field.type) {
      case SettingType::kInt: json[key] = static_cast<long long>(value); break;
      case SettingType::kDouble: json[key] = value; break;
      case SettingType::kBool: json[key] = value != 0; break;
      case SettingType::kChoice: json[key] = field.format(settings); break;
    }
  }
  // Only when given: the records and reports of matches without landmarks stay as they were
  // (a stored result is found again by the digest of this object).
  if (!settings.landmarks.empty()) {
    nlohmann::json& list = json["landmarks"] = nlohmann::json::array();
    for (const Landmark& l : settings.landmarks)
      list.push_back({{"source_vertex", l.source_vertex}, {"target_vertex", l.target_vertex}});
  }
  return json;
}

MatchSettings settings_from_json(const nlohmann::json& json) {
  MatchSettings settings;
  for (const auto& field : settings_schema()) {
    const auto it = json.find(std::string(field.name));
    if (it == json.end()) continue;
    const bool fits = field.type == SettingType::kBool     ? it->is_boolean()
                      : field.type == SettingType::kChoice ? it->is_string()
                      : field.type == SettingType::kInt    ? it->is_number_integer()
                                                           : it->is_number();
    if (!fits) throw InputError("setting " + std::string(field.name) + " has the wrong JSON type");
    // The members are 32-bit ints: a wider JSON integer would not convert (found by fuzzing).
    if (field.type == SettingType::kInt &&
        !(it->get<double>() >= std::numeric_limits<int>::min() && it->get<double>() <= std::numeric_limits<int>::max()))
      throw InputError("setting " + std::string(field.name) + " is not an integer within 32 bits");
    if (field.type == SettingType::kBool) field.set(settings, it->get<bool>() ? 1 : 0);
    else if (field.type == SettingType::kChoice) field.parse(settings, it->get<std::string>());
    else field.set(settings, it->get<double>());
  }
  if (const auto it = json.find("landmarks"); it != json.end()) {
    if (!it->is_array()) throw InputError("setting landmarks is not a list");
    for (size_t i = 0; i < it->size(); ++i) settings.landmarks.push_back(landmark_from_json((*it)[i], i));
  }
  return settings;
}

}  // namespace isocorr

#include "isocorr/settings/settings_json.h"

#include <limits>

#include "isocorr/settings/settings_schema.h"
#include "isocorr/util/error.h"

namespace isocorr {

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
  return settings;
}

}  // namespace isocorr

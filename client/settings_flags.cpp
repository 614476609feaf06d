#include "settings_flags.h"

#include <CLI/CLI.hpp>

#include "isocorr/settings/settings_schema.h"

namespace isocorr::cli {

void add_match_settings_flags(CLI::App& app, MatchSettings& settings) {
  const MatchSettings defaults;
  for (const SettingField& field : settings_schema()) {
    std::string help(field.help);
    if (field.type == SettingType::kInt || field.type == SettingType::kDouble)
      help += "; range " + field.range.describe();
    app.add_option_function<std::string>(
           field.flag(),
           [&settings, &field](const std::string& text) {
             try {
               field.parse(settings, text);
             } catch (const InputError& e) {
               throw CLI::ValidationError(field.flag(), e.what());
             }
           },
           help)
        ->type_name(field.type == SettingType::kChoice ? "CHOICE"
                    : field.type == SettingType::kBool ? "BOOL"
                    : field.type == SettingType::kInt  ? "INT"
                                                       : "FLOAT")
        ->default_str(field.format(defaults))
        ->group("Matching settings");
  }
  app.add_flag_callback(
         "--partial", [&settings] { settings.method = MatchMethod::kPart; },
         "the source is a part of the target's shape (short for --method part): the reverse map has -1 "
         "where the target has no counterpart")
      ->group("Matching settings");
}

}  // namespace isocorr::cli

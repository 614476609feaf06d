#include "settings_flags.h"

#include <cctype>
#include <map>
#include <string_view>

#include <CLI/CLI.hpp>

#include "isocorr/settings/settings_schema.h"

namespace isocorr::cli {
namespace {

// The settings table's sections, each under its own heading in --help: the first field of
// each section and the heading.
const std::map<std::string_view, const char*> kSectionStarts = {
    {"level0_samples", "Level 0 (coarsest match)"},
    {"min_tracked", "Tracking and the choice of a tracked map"},
    {"dense_anchors", "Dense level"},
    {"method", "Problem (complete or partial shapes)"},
    {"refine", "Refinement and the choice by dense evidence"},
    {"level0_radius", "Per-mesh preprocessing"},
    {"threads", "This process"},
};

bool is_name_character(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

}  // namespace

std::string with_flag_names(std::string text) {
  for (const SettingField& field : settings_schema()) {
    // One-word names ("method") read the same either way and are common words: only names
    // with an underscore, or written as "settings.name", are taken for settings.
    const bool compound = field.name.find('_') != std::string_view::npos;
    for (size_t at = text.find(field.name); at != std::string::npos; at = text.find(field.name, at + 1)) {
      const size_t end = at + field.name.size();
      if ((at > 0 && is_name_character(text[at - 1])) || (end < text.size() && is_name_character(text[end]))) continue;
      const bool qualified = at >= 9 && text.compare(at - 9, 9, "settings.") == 0;
      if (!compound && !qualified) continue;
      const size_t from = qualified ? at - 9 : at;
      text.replace(from, end - from, field.flag());
      at = from;
    }
  }
  return text;
}

void add_match_settings_flags(CLI::App& app, MatchSettings& settings, LandmarksFile& landmarks_file) {
  const MatchSettings defaults;
  std::string group = "Matching settings";
  for (const SettingField& field : settings_schema()) {
    if (const auto start = kSectionStarts.find(field.name); start != kSectionStarts.end())
      group = std::string("Matching settings: ") + start->second;
    std::string help = with_flag_names(std::string(field.help));
    if (field.type == SettingType::kInt || field.type == SettingType::kDouble)
      help += "; range " + field.range.describe();
    app.add_option_function<std::string>(
           field.flag(),
           [&settings, &field](const std::string& text) {
             try {
               field.parse(settings, text);
             } catch (const InputError& e) {
               throw CLI::ValidationError(field.flag(), with_flag_names(e.what()));
             }
           },
           help)
        ->type_name(field.type == SettingType::kChoice ? "CHOICE"
                    : field.type == SettingType::kBool ? "BOOL"
                    : field.type == SettingType::kInt  ? "INT"
                                                       : "FLOAT")
        ->default_str(field.format(defaults))
        ->group(group);
    if (field.name == "method")
      app.add_flag_callback(
             "--partial", [&settings] { settings.method = MatchMethod::kPart; },
             "the source is a part of the target's shape (short for --method part): the reverse map has -1 "
             "where the target has no counterpart")
          ->group(group);
  }
  // Not a row of the table: a list (settings_schema.cpp).
  app.add_option_function<std::string>(
         "--landmarks",
         [&settings, &landmarks_file](const std::string& path) {
           try {
             read_landmarks_file(path, settings.landmarks, landmarks_file);
           } catch (const InputError& e) {
             throw CLI::ValidationError("--landmarks", e.what());
           }
         },
         "known correspondences: a file of 'source_vertex target_vertex' lines (0-based, the files' numbering; "
         "# comments). Level-0 maps and refined candidates that disagree with them are dropped, and the maps send "
         "each to its partner")
      ->type_name("FILE")
      ->group("Matching settings: Landmarks");
}

}  // namespace isocorr::cli

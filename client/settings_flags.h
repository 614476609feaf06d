// Command-line flags for every engine setting, derived from the settings table and shared
// by `isocorr match`, `isocorr submit` and the benchmark.
#pragma once

#include <string>

#include "isocorr/settings/match_settings.h"
#include "landmarks_file.h"

namespace CLI {
class App;
}

namespace isocorr::cli {

// Registers one flag per row of the settings table (--name-with-dashes), its help with the
// range and the default, grouped by the table's sections, and --landmarks FILE
// (landmarks_file.h), whose lines land in `landmarks_file`. Parsed values land in
// `settings`; malformed text is a CLI error. Both must outlive parsing.
void add_match_settings_flags(CLI::App& app, MatchSettings& settings, LandmarksFile& landmarks_file);

// `text` (a help text or an engine message) with every setting named as its flag:
// "zoomout_k_end" and "settings.zoomout_k_end" become "--zoomout-k-end".
std::string with_flag_names(std::string text);

}  // namespace isocorr::cli

// Command-line flags for every engine setting, derived from the settings table and shared
// by `isocorr match`, `isocorr submit` and the benchmark.
#pragma once

#include "isocorr/settings/match_settings.h"

namespace CLI {
class App;
}

namespace isocorr::cli {

// Registers one flag per row of the settings table (--name-with-dashes), its help with the
// range and the default. Parsed values land in `settings`; malformed text is a CLI error.
// `settings` must outlive parsing.
void add_match_settings_flags(CLI::App& app, MatchSettings& settings);

}  // namespace isocorr::cli

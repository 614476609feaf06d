// Command-line flags for every engine setting, shared by `isocorr match` and the benchmark.
#pragma once

#include <string>

#include "isocorr/matching/matcher.h"

namespace CLI {
class App;
}

namespace isocorr::cli {

// Registers one flag per MatchSettings member, with the default shown in --help.
// `selection` receives the rule name; call apply_selection afterwards.
void add_match_settings_flags(CLI::App& app, MatchSettings& settings, std::string& selection);
void apply_selection(const std::string& selection, MatchSettings& settings);

}  // namespace isocorr::cli

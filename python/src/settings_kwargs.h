// Settings as Python keyword arguments: the names of the settings table (the CLI's flags
// with underscores, the API's fields), checked against its ranges.
#pragma once

#include <pybind11/pybind11.h>

#include "isocorr/settings/match_settings.h"
#include "isocorr/settings/settings_schema.h"

namespace isocorr::python {

namespace py = pybind11;

// `settings` with each keyword of `kwargs` set; raises ValueError naming an unknown
// setting, a value of the wrong type, or one outside its range. Only settings of the
// `allowed` scopes are taken; the error for another says where it belongs.
void apply_settings(const py::kwargs& kwargs, const std::vector<SettingScope>& allowed, MatchSettings& settings);

// isocorr.settings(): the table as a list of dicts (name, default, type, range, choices,
// scope, help).
void register_settings_functions(py::module_& module);

}  // namespace isocorr::python

#include "settings_kwargs.h"

#include <pybind11/numpy.h>

#include <algorithm>
#include <cstdint>
#include <string>

#include "isocorr/util/error.h"

namespace isocorr::python {
namespace {

const char* scope_name(SettingScope scope) {
  switch (scope) {
    case SettingScope::kMatch: return "match";
    case SettingScope::kPreprocess: return "preprocess";
    case SettingScope::kLocal: return "local";
  }
  return "";
}

// The value as the table's text (SettingField::parse), refusing Python types that do not
// fit the field: a bool for a number, a number for a choice, a fraction for an integer.
std::string setting_text(const SettingField& field, const py::handle& value) {
  const std::string name(field.name);
  const bool is_bool = py::isinstance<py::bool_>(value);
  switch (field.type) {
    case SettingType::kBool:
      if (!is_bool) throw py::value_error(name + " takes True or False, got " + std::string(py::repr(value)));
      return value.cast<bool>() ? "true" : "false";
    case SettingType::kChoice:
      if (!py::isinstance<py::str>(value)) {
        std::string names;
        for (const std::string_view choice : field.choices) names += (names.empty() ? "'" : ", '") + std::string(choice) + "'";
        throw py::value_error(name + " takes one of " + names + ", got " + std::string(py::repr(value)));
      }
      return value.cast<std::string>();
    case SettingType::kInt:
      if (is_bool || !py::isinstance<py::int_>(value))
        throw py::value_error(name + " takes an integer, got " + std::string(py::repr(value)));
      return std::to_string(value.cast<long long>());
    case SettingType::kDouble:
      if (is_bool || !(py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value)))
        throw py::value_error(name + " takes a number, got " + std::string(py::repr(value)));
      return std::string(py::repr(py::float_(value.cast<double>())));
  }
  return "";
}

}  // namespace

// landmarks=: pairs (source vertex, target vertex), an (n, 2) integer array or a list of
// pairs; the match validates them against the meshes.
static std::vector<Landmark> landmarks_argument(const py::handle& value) {
  const auto array = value.cast<py::array_t<int64_t, py::array::c_style | py::array::forcecast>>();
  if (array.ndim() != 2 || array.shape(1) != 2)
    throw py::value_error("landmarks must be pairs (source vertex, target vertex): an array of shape (n, 2)");
  const auto pairs = array.unchecked<2>();
  std::vector<Landmark> landmarks;
  for (py::ssize_t i = 0; i < array.shape(0); ++i) {
    if (pairs(i, 0) < 0 || pairs(i, 1) < 0 || pairs(i, 0) > INT32_MAX || pairs(i, 1) > INT32_MAX)
      throw py::value_error("landmarks[" + std::to_string(i) + "] is no pair of vertex indices");
    landmarks.push_back({static_cast<int>(pairs(i, 0)), static_cast<int>(pairs(i, 1))});
  }
  return landmarks;
}

void apply_settings(const py::kwargs& kwargs, const std::vector<SettingScope>& allowed, MatchSettings& settings) {
  for (const auto& [key, value] : kwargs) {
    const std::string name = key.cast<std::string>();
    if (name == "landmarks" &&
        std::find(allowed.begin(), allowed.end(), SettingScope::kMatch) != allowed.end()) {
      settings.landmarks = landmarks_argument(value);
      continue;
    }
    const SettingField* field = find_setting(name);
    if (!field) throw py::value_error("unknown setting '" + name + "' (isocorr.settings() lists them)");
    if (std::find(allowed.begin(), allowed.end(), field->scope) == allowed.end())
      throw py::value_error(name + (field->scope == SettingScope::kPreprocess
                                        ? " is a preprocessing setting: give it to isocorr.Shape"
                                        : " is a setting of the match: give it to isocorr.match"));
    try {
      field->parse(settings, setting_text(*field, value));
      field->check(settings);
    } catch (const InputError& e) {
      throw py::value_error(e.what());
    }
  }
}

void register_settings_functions(py::module_& module) {
  module.def(
      "settings",
      [] {
        const MatchSettings defaults;
        py::list table;
        for (const SettingField& field : settings_schema()) {
          py::dict row;
          row["name"] = std::string(field.name);
          row["default"] = field.format(defaults);
          row["type"] = field.type == SettingType::kInt      ? "int"
                        : field.type == SettingType::kDouble ? "float"
                        : field.type == SettingType::kBool   ? "bool"
                                                             : "choice";
          row["range"] = field.type == SettingType::kInt || field.type == SettingType::kDouble
                             ? py::object(py::str(field.range.describe()))
                             : py::object(py::none());
          py::list choices;
          for (const std::string_view choice : field.choices) choices.append(std::string(choice));
          row["choices"] = choices;
          row["scope"] = scope_name(field.scope);
          row["help"] = std::string(field.help);
          table.append(row);
        }
        return table;
      },
      R"(The settings isocorr.Shape and isocorr.match take, as a list of dicts: name, default
(as text), type, range, choices, scope ('preprocess' for Shape, 'match' and 'local' for match)
and help.)");
}

}  // namespace isocorr::python

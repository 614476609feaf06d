#include "isocorr/settings/settings_schema.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <type_traits>

#include "isocorr/transfer/landmarks.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

constexpr double kNoLimit = std::numeric_limits<int>::max();

SettingRange closed(double min, double max) { return {min, max, false, false}; }
SettingRange open_closed(double min, double max) { return {min, max, true, false}; }
SettingRange closed_open(double min, double max) { return {min, max, false, true}; }
SettingRange open(double min, double max) { return {min, max, true, true}; }

// One row: `access` is a generic lambda returning a reference to the member, so the
// member's type decides the field's type and both directions are written once.
template <class Access>
SettingField row(std::string_view name, SettingScope scope, SettingRange range, std::string_view help,
                 Access access, std::vector<std::string_view> choices = {}) {
  using Member = std::remove_reference_t<decltype(access(std::declval<MatchSettings&>()))>;
  SettingField field;
  field.name = name;
  field.help = help;
  field.scope = scope;
  field.range = range;
  field.choices = std::move(choices);
  if constexpr (std::is_same_v<Member, bool>) {
    field.type = SettingType::kBool;
    field.range = closed(0, 1);
  } else if constexpr (std::is_enum_v<Member>) {
    field.type = SettingType::kChoice;
    field.range = closed(0, static_cast<double>(field.choices.size()) - 1);
  } else if constexpr (std::is_integral_v<Member>) {
    field.type = SettingType::kInt;
  } else {
    field.type = SettingType::kDouble;
  }
  field.get = [access](const MatchSettings& s) {
    const Member value = access(const_cast<MatchSettings&>(s));
    if constexpr (std::is_enum_v<Member>) return static_cast<double>(static_cast<int>(value));
    else return static_cast<double>(value);
  };
  field.set = [access](MatchSettings& s, double value) {
    if constexpr (std::is_enum_v<Member>) access(s) = static_cast<Member>(static_cast<int>(value));
    else access(s) = static_cast<Member>(value);
  };
  return field;
}

constexpr SettingScope kMatch = SettingScope::kMatch;
constexpr SettingScope kPreprocess = SettingScope::kPreprocess;

// Level 0.
std::vector<SettingField> level0_rows() {
  return {
    row("level0_samples", kMatch, closed(0, 10),
        "M: source samples at level 0 (0 = the number of source extremities, within [5, 7]; else at least 3)",
        [](auto& s) -> auto& { return s.level0_samples; }),
    row("level0_extra_targets", kMatch, closed(0, 3), "M' - M: extra target samples at level 0",
        [](auto& s) -> auto& { return s.level0_extra_targets; }),
    row("max_level0_diso", kMatch, open_closed(0, 1), "level-0 maps above this D_iso are dropped",
        [](auto& s) -> auto& { return s.max_level0_diso; }),
    row("max_level0_maps", kMatch, closed(1, kNoLimit), "keep at most this many sorted level-0 maps",
        [](auto& s) -> auto& { return s.max_level0_maps; }),
  };
}

// Tracking and the choice among tracked maps.
std::vector<SettingField> tracking_rows() {
  return {
    row("min_tracked", kMatch, closed(1, kNoLimit), "track at least this many level-0 maps",
        [](auto& s) -> auto& { return s.min_tracked; }),
    row("max_tracked", kMatch, closed(1, kNoLimit),
        "track at most this many level-0 maps (the jump rule decides within)",
        [](auto& s) -> auto& { return s.max_tracked; }),
    row("selection", kMatch, {}, "choice among tracked maps: orientation, or least-diso (the paper's rule)",
        [](auto& s) -> auto& { return s.selection; }, {"orientation", "least-diso"}),
    row("orientation_threshold", kMatch, closed(0, 1),
        "tracked maps keeping fewer triangles' handedness are mirrored",
        [](auto& s) -> auto& { return s.orientation_threshold; }),
    row("orientation_margin", kMatch, closed(0, 1),
        "tracked maps this close to the best orientation compete on D_iso",
        [](auto& s) -> auto& { return s.orientation_margin; }),
    row("orientation_weight", kMatch, closed(0, 1),
        "among those, the choice minimises D_iso - weight * orientation agreement",
        [](auto& s) -> auto& { return s.orientation_weight; }),
    row("handedness_guard", kMatch, {},
        "tracking only accepts images that keep the handedness of nearby pairs",
        [](auto& s) -> auto& { return s.tracking.handedness_guard; }),
    row("pool_all_levels", kMatch, {}, "tracking offers every target sample at every level",
        [](auto& s) -> auto& { return s.tracking.pool_all_levels; }),
    row("anchor_cap", kMatch, closed(3, kNoLimit), "anchors used for d_iso while tracking",
        [](auto& s) -> auto& { return s.tracking.anchor_cap; }),
    row("trim_fraction", kMatch, closed_open(0, 0.9),
        "share of the worst d_iso terms ignored when matching a sample",
        [](auto& s) -> auto& { return s.tracking.trim_fraction; }),
    row("window_factor", kMatch, open_closed(0, 1000),
        "search window around the parent's image, in parent distances",
        [](auto& s) -> auto& { return s.tracking.window_factor; }),
  };
}

// The C2F dense level (refine = none).
std::vector<SettingField> dense_level_rows() {
  return {
    row("dense_anchors", kMatch, closed(3, kNoLimit), "E: anchors describing each vertex in the dense level",
        [](auto& s) -> auto& { return s.dense.anchor_count; }),
    row("dense_outliers", kMatch, closed_open(0, 1),
        "at most this share of the tracked pairs is dropped as dense anchors",
        [](auto& s) -> auto& { return s.dense.outlier_fraction; }),
    row("dense_outlier_ratio", kMatch, closed(1, kNoLimit),
        "... and only pairs whose distortion exceeds this many medians",
        [](auto& s) -> auto& { return s.dense.outlier_ratio; }),
    row("dense_refinement_rounds", kMatch, closed(0, 20), "rounds moving dense anchor images to vertex accuracy",
        [](auto& s) -> auto& { return s.dense.anchor_refinement_rounds; }),
    row("dense_locality", kMatch, closed(0, 10),
        "dense level: anchors weigh 1/(distance + this); 0 = plain d_iso",
        [](auto& s) -> auto& { return s.dense.locality; }),
  };
}

// Which problem: complete shapes, or a part of the target's shape.
std::vector<SettingField> problem_rows() {
  return {
    row("method", kMatch, {},
        "full (both meshes complete), part (the source is a part of the target's shape) or ravac (either may "
        "be partial)",
        [](auto& s) -> auto& { return s.method; }, {"full", "part", "ravac"}),
    row("part_extremities", kMatch, closed(3, 7), "part matching: source extremities matched combinatorially (M)",
        [](auto& s) -> auto& { return s.part_extremities; }),
    row("part_candidates", kMatch, closed(1, 256), "part matching (part, ravac): extremity maps grown to sample maps and compared",
        [](auto& s) -> auto& { return s.part_candidates; }),
  };
}

// Refinement: the screen, ZoomOut and the spectral and curvature polish.
std::vector<SettingField> refinement_rows() {
  return {
    row("refine", kMatch, {}, "after tracking: zoomout (spectral refinement, choice by dense evidence) or none (the C2F dense level)",
        [](auto& s) -> auto& { return s.refine; }, {"zoomout", "none"}),
    row("screen_candidates", kMatch, closed(1, 64),
        "distinct tracked maps screened by a short spectral refinement on the samples; the refine_candidates whose curvature agrees best go on",
        [](auto& s) -> auto& { return s.screen_candidates; }),
    row("screen_k_end", kMatch, closed(1, 1000), "basis size the screening refinement stops at (at most zoomout_k_end)",
        [](auto& s) -> auto& { return s.screen_k_end; }),
    row("refine_candidates", kMatch, closed(1, 32),
        "screened tracked maps refined fully; the 3 whose curvature agrees best are finished and compared",
        [](auto& s) -> auto& { return s.refine_candidates; }),
    row("zoomout_k_start", kMatch, closed(1, 1000), "spectral refinement: first basis size",
        [](auto& s) -> auto& { return s.zoomout.k_start; }),
    row("zoomout_k_end", kMatch, closed(1, 1000), "spectral refinement: last basis size (at most spectral_basis)",
        [](auto& s) -> auto& { return s.zoomout.k_end; }),
    row("zoomout_k_step", kMatch, closed(1, 1000), "spectral refinement: basis growth per iteration",
        [](auto& s) -> auto& { return s.zoomout.k_step; }),
    row("zoomout_dense_iterations", kMatch, closed(0, 20),
        "spectral refinement: refits of the functional map on every vertex after the sampled iterations",
        [](auto& s) -> auto& { return s.zoomout.dense_iterations; }),
    row("zoomout_polish_k_end", kMatch, closed(0, 1000),
        "spectral refinement: the chosen map is refined on every vertex up to this basis size (at most zoomout_k_end: no polish)",
        [](auto& s) -> auto& { return s.zoomout.polish_k_end; }),
    row("zoomout_polish_k_step", kMatch, closed(1, 1000), "spectral refinement: basis growth per polish step",
        [](auto& s) -> auto& { return s.zoomout.polish_k_step; }),
    row("zoomout_commutativity", kMatch, closed(0, 1000),
        "spectral refinement: weight of the Laplacian commutativity term in each functional-map fit (0 = none; "
        "full-shape matching only: a part's spectrum is not the whole's)",
        [](auto& s) -> auto& { return s.zoomout.commutativity; }),
    row("zoomout_curvature_weight", kMatch, closed(0, 1000),
        "spectral refinement: weight of the smoothed mean and Gaussian curvature in the chosen map's last refits, which "
        "correct slides along the surface that intrinsic cues cannot see (0 = none)",
        [](auto& s) -> auto& { return s.zoomout.curvature_weight; }),
    row("zoomout_curvature_iterations", kMatch, closed(0, 100),
        "spectral refinement: refits on the samples with the curvature term before its refit on every vertex",
        [](auto& s) -> auto& { return s.zoomout.curvature_iterations; }),
    row("zoomout_curvature_candidates", kMatch, closed(0, 100000),
        "spectral refinement: the curvature term also picks each sample's image during the polish's basis growth, "
        "among this many spectrally nearest target samples (0 = growth without it)",
        [](auto& s) -> auto& { return s.zoomout.curvature_candidates; }),
  };
}

// Finishing the refined maps, and the choice by dense evidence.
std::vector<SettingField> finishing_rows() {
  return {
    row("outlier_repair", kMatch, {},
        "each refined map's vertices that break geodesic distances to its anchors far more than the rest are placed again",
        [](auto& s) -> auto& { return s.outlier_repair; }),
    row("rigidity_iterations", kMatch, closed(0, 1000),
        "rigidity polish of each refined map and of a part search map: as-rigid-as-possible iterations per fit weight (0 = none)",
        [](auto& s) -> auto& { return s.rigidity.iterations; }),
    row("mirror_repair", kMatch, {},
        "the rigidity polish also starts from each map with its mirrored limb segments (held at both ends) placed again, and keeps the lower-energy result",
        [](auto& s) -> auto& { return s.rigidity.mirror_repair; }),
    row("rigidity_final_iterations", kMatch, closed(0, 1000),
        "the chosen map's further rigidity polish, iterations per fit weight, kept only where its curvature agrees better (0 = none)",
        [](auto& s) -> auto& { return s.rigidity_final_iterations; }),
    row("refine_passes", kMatch, closed(0, 5),
        "the chosen map refined again from itself this many times, ZoomOut starting at half of zoomout_k_end (0 = none)",
        [](auto& s) -> auto& { return s.refine_passes; }),
    row("dense_choice_sources", kMatch, closed(1, 64),
        "geodesic fields per refined candidate for its dense distortion",
        [](auto& s) -> auto& { return s.dense_choice_sources; }),
  };
}

// Per-mesh preprocessing.
std::vector<SettingField> preprocessing_rows() {
  return {
    row("level0_radius", kPreprocess, open(0, 1), "level-0 sampling radius, fraction of the geodesic diameter",
        [](auto& s) -> auto& { return s.preprocess.level0_radius; }),
    row("level_shrink", kPreprocess, open(0, 1), "sampling radius factor between levels",
        [](auto& s) -> auto& { return s.preprocess.level_shrink; }),
    row("decision_level", kPreprocess, closed(1, 12), "K1: level at which tracked maps are compared",
        [](auto& s) -> auto& { return s.preprocess.decision_level; }),
    row("max_level0_samples", kPreprocess, closed(3, 12), "level-0 samples kept per mesh (M' is at most this)",
        [](auto& s) -> auto& { return s.preprocess.max_level0_samples; }),
    row("spectral_basis", kPreprocess, closed(0, 1000), "Laplace-Beltrami eigenpairs per mesh (0 = none: no refinement)",
        [](auto& s) -> auto& { return s.preprocess.spectral_basis; }),
    row("spectral_samples", kPreprocess, closed(100, 100000), "evenly spread vertices per mesh the refinement iterates on",
        [](auto& s) -> auto& { return s.preprocess.spectral_samples; }),
    row("spectral_cells", kPreprocess, closed(0, 1000000),
        "meshes with more vertices solve the eigenproblem reduced to this many cells (0 = never)",
        [](auto& s) -> auto& { return s.preprocess.spectral_cells; }),
    row("agd_sources", kPreprocess, closed(1, 10000), "farthest-point fields averaged for saliency",
        [](auto& s) -> auto& { return s.preprocess.saliency.agd_sources; }),
    row("extremity_radius", kPreprocess, open_closed(0, 1),
        "radius within which an extremity is the AGD maximum, fraction of the diameter",
        [](auto& s) -> auto& { return s.preprocess.saliency.extremity_radius; }),
    row("weld_tolerance", kPreprocess, closed(0, 0.01),
        "open-surface vertices closer than this fraction of the bounding-box diagonal are welded",
        [](auto& s) -> auto& { return s.preprocess.cleaning.weld_tolerance; }),
    row("keep_largest_component", kPreprocess, {},
        "keep the largest connected component (else several components are an error)",
        [](auto& s) -> auto& { return s.preprocess.cleaning.keep_largest_component; }),
    row("repair_non_manifold_edges", kPreprocess, {},
        "repair edges shared by more than two faces (else they are an error)",
        [](auto& s) -> auto& { return s.preprocess.cleaning.repair_non_manifold_edges; }),
  };
}

// This process.
std::vector<SettingField> process_rows() {
  return {
    row("threads", SettingScope::kLocal, closed(0, 1024), "worker threads (0 = all cores); results do not depend on it",
        [](auto& s) -> auto& { return s.threads; }),
  };
}

// MatchSettings::landmarks is not a row: a row is one number (get/set as a double), which
// is what lets the flags, the codec's reflection and the JSON walk every row alike, and a
// list of vertex pairs is not one. So each of those handles it beside the table, in the
// same places: MatchSettings::validate and same_settings below, settings_json.cpp, the
// proto's repeated `landmarks` (codec/settings_codec.cpp) and the CLI's --landmarks FILE
// (client/settings_flags.cpp). It is per match, so settings_key never includes it.
std::vector<SettingField> build_schema() {
  // Ranges are what the algorithms can run with, not what is sensible: the defaults and
  // their measured reasons are beside the members.
  using Section = std::vector<SettingField> (*)();
  std::vector<SettingField> schema;
  for (const Section section : {level0_rows, tracking_rows, dense_level_rows, problem_rows, refinement_rows,
                                finishing_rows, preprocessing_rows, process_rows})
    for (SettingField& field : section()) schema.push_back(std::move(field));
  return schema;
}

// The shortest text that parses back to exactly `value` (0.15, not 0.14999999999999999).
std::string format_number(double value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

}  // namespace

bool SettingRange::contains(double value) const {
  if (std::isnan(value)) return false;
  const bool above = min_open ? value > min : value >= min;
  const bool below = max_open ? value < max : value <= max;
  return above && below;
}

std::string SettingRange::describe() const {
  auto bound = [](double v) { return v >= kNoLimit ? std::string("inf") : format_number(v); };
  return std::string(min_open ? "(" : "[") + bound(min) + ", " + bound(max) + (max_open || max >= kNoLimit ? ")" : "]");
}

std::string SettingField::flag() const {
  std::string text = "--" + std::string(name);
  std::replace(text.begin(), text.end(), '_', '-');
  return text;
}

std::string SettingField::format(const MatchSettings& settings) const {
  const double value = get(settings);
  switch (type) {
    case SettingType::kBool: return value != 0 ? "true" : "false";
    case SettingType::kChoice: return std::string(choices.at(static_cast<size_t>(value)));
    case SettingType::kInt: return std::to_string(static_cast<long long>(value));
    case SettingType::kDouble: break;
  }
  return format_number(value);
}

void SettingField::parse(MatchSettings& settings, const std::string& text) const {
  auto bad = [&](const std::string& expected) {
    return InputError("setting " + std::string(name) + ": '" + text.substr(0, 40) + "' is not " + expected);
  };
  switch (type) {
    case SettingType::kBool:
      if (text == "true" || text == "1" || text == "yes" || text == "on") return set(settings, 1);
      if (text == "false" || text == "0" || text == "no" || text == "off") return set(settings, 0);
      throw bad("true or false");
    case SettingType::kChoice:
      for (size_t i = 0; i < choices.size(); ++i)
        if (text == choices[i]) return set(settings, static_cast<double>(i));
      {
        std::string names;
        for (const auto c : choices) names += (names.empty() ? "" : ", ") + std::string(c);
        throw bad("one of " + names);
      }
    case SettingType::kInt: {
      long long value = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (error != std::errc() || end != text.data() + text.size() || text.empty()) throw bad("an integer");
      if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
        throw bad("an integer within 32 bits");
      return set(settings, static_cast<double>(value));
    }
    case SettingType::kDouble: {
      double value = 0;
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (error != std::errc() || end != text.data() + text.size() || text.empty() || !std::isfinite(value))
        throw bad("a finite number");
      return set(settings, value);
    }
  }
}

void SettingField::check(const MatchSettings& settings) const {
  if (type == SettingType::kBool || type == SettingType::kChoice) return;  // every value is valid
  const double value = get(settings);
  if (!range.contains(value))
    throw InputError("setting " + std::string(name) + " = " + format(settings) + " is out of range " +
                     range.describe());
}

const std::vector<SettingField>& settings_schema() {
  static const std::vector<SettingField> schema = build_schema();
  return schema;
}

const SettingField* find_setting(std::string_view name) {
  for (const auto& field : settings_schema())
    if (field.name == name) return &field;
  return nullptr;
}

std::string settings_key(const MatchSettings& settings, SettingScope scope) {
  std::string key;
  for (const auto& field : settings_schema())
    if (field.scope == scope) key += std::string(field.name) + "=" + field.format(settings) + ";";
  return key;
}

void validate_preprocess_options(const PreprocessOptions& options) {
  MatchSettings settings;
  settings.preprocess = options;
  for (const auto& field : settings_schema())
    if (field.scope == SettingScope::kPreprocess) field.check(settings);
}

bool same_settings(const MatchSettings& a, const MatchSettings& b) {
  for (const auto& field : settings_schema())
    if (field.get(a) != field.get(b)) return false;
  return a.landmarks == b.landmarks;
}

void MatchSettings::validate() const {
  for (const auto& field : settings_schema()) field.check(*this);
  if (level0_samples != 0 && level0_samples < 3)
    throw InputError("setting level0_samples = " + std::to_string(level0_samples) +
                     ": M must be 0 (automatic) or at least 3");
  if (max_tracked < min_tracked)
    throw InputError("setting max_tracked = " + std::to_string(max_tracked) + " is below min_tracked = " +
                     std::to_string(min_tracked));
  if (refine != RefineMethod::kNone && zoomout.k_end > preprocess.spectral_basis)
    throw InputError("setting zoomout_k_end = " + std::to_string(zoomout.k_end) + " exceeds spectral_basis = " +
                     std::to_string(preprocess.spectral_basis) + ", the eigenpairs kept per mesh (or use refine = none)");
  if (refine != RefineMethod::kNone && zoomout.polish_k_end > preprocess.spectral_basis)
    throw InputError("setting zoomout_polish_k_end = " + std::to_string(zoomout.polish_k_end) +
                     " exceeds spectral_basis = " + std::to_string(preprocess.spectral_basis));
  if (zoomout.k_start > zoomout.k_end)
    throw InputError("setting zoomout_k_start = " + std::to_string(zoomout.k_start) + " exceeds zoomout_k_end = " +
                     std::to_string(zoomout.k_end));
  if (std::max(level0_samples, 7) + level0_extra_targets > preprocess.max_level0_samples)
    throw InputError("settings level0_samples + level0_extra_targets (M') exceed max_level0_samples = " +
                     std::to_string(preprocess.max_level0_samples) + ", the level-0 samples kept per mesh");
  validate_landmarks(landmarks);
}

}  // namespace isocorr

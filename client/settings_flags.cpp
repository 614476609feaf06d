#include "settings_flags.h"

#include <CLI/CLI.hpp>

namespace isocorr::cli {

void add_match_settings_flags(CLI::App& app, MatchSettings& s, std::string& selection) {
  const char* group = "Matching settings";
  app.add_option("--level0-samples", s.level0_samples, "M: source samples at level 0 (0 = the number of source extremities, within [5, 7])")->group(group)->capture_default_str();
  app.add_option("--level0-extra-targets", s.level0_extra_targets, "M' - M: extra target samples at level 0")->group(group)->capture_default_str();
  app.add_option("--max-level0-diso", s.max_level0_diso, "level-0 maps above this D_iso are dropped")->group(group)->capture_default_str();
  app.add_option("--max-level0-maps", s.max_level0_maps, "keep at most this many sorted level-0 maps")->group(group)->capture_default_str();
  app.add_option("--min-tracked", s.min_tracked, "track at least this many level-0 maps")->group(group)->capture_default_str();
  app.add_option("--max-tracked", s.max_tracked, "track at most this many level-0 maps (jump rule decides within)")->group(group)->capture_default_str();
  app.add_option("--selection", selection, "choice among tracked maps: orientation (default) or least-diso (the paper's rule)")
      ->group(group)->check(CLI::IsMember({"orientation", "least-diso"}))->capture_default_str();
  app.add_option("--orientation-threshold", s.orientation_threshold, "tracked maps keeping fewer triangles' handedness are mirrored")->group(group)->capture_default_str();
  app.add_option("--orientation-margin", s.orientation_margin, "tracked maps this close to the best orientation compete on D_iso")->group(group)->capture_default_str();
  app.add_option("--orientation-weight", s.orientation_weight, "among those, the choice minimises D_iso - weight * orientation agreement")->group(group)->capture_default_str();
  app.add_option("--handedness-guard", s.tracking.handedness_guard, "tracking only accepts images that keep the handedness of nearby pairs (true/false)")->group(group)->capture_default_str();
  app.add_option("--anchor-cap", s.tracking.anchor_cap, "anchors used for d_iso while tracking")->group(group)->capture_default_str();
  app.add_option("--trim-fraction", s.tracking.trim_fraction, "share of the worst d_iso terms ignored when matching a sample")->group(group)->capture_default_str();
  app.add_option("--window-factor", s.tracking.window_factor, "search window around the parent's image, in parent distances")->group(group)->capture_default_str();
  app.add_option("--dense-anchors", s.dense.anchor_count, "E: anchors describing each vertex in the dense level")->group(group)->capture_default_str();
  app.add_option("--dense-outliers", s.dense.outlier_fraction, "at most this share of the tracked pairs is dropped as dense anchors")->group(group)->capture_default_str();
  app.add_option("--dense-outlier-ratio", s.dense.outlier_ratio, "... and only pairs whose distortion exceeds this many medians")->group(group)->capture_default_str();
  app.add_option("--dense-locality", s.dense.locality, "dense level: anchors weigh 1/(distance + this); 0 = plain d_iso")->group(group)->capture_default_str();
  app.add_option("--level0-radius", s.preprocess.level0_radius, "level-0 sampling radius, fraction of the geodesic diameter")->group(group)->capture_default_str();
  app.add_option("--level-shrink", s.preprocess.level_shrink, "sampling radius factor between levels")->group(group)->capture_default_str();
  app.add_option("--decision-level", s.preprocess.decision_level, "K1: level at which tracked maps are compared")->group(group)->capture_default_str();
  app.add_option("--agd-sources", s.preprocess.saliency.agd_sources, "farthest-point fields averaged for saliency")->group(group)->capture_default_str();
  app.add_option("--extremity-radius", s.preprocess.saliency.extremity_radius, "radius within which an extremity is the AGD maximum")->group(group)->capture_default_str();
  app.add_option("--threads", s.threads, "worker threads (0 = all cores); results do not depend on it")->group(group)->capture_default_str();
}

void apply_selection(const std::string& selection, MatchSettings& settings) {
  settings.selection = selection == "least-diso" ? SelectionRule::kLeastDistortion
                                                 : SelectionRule::kOrientationThenDistortion;
}

}  // namespace isocorr::cli

#include "codec/settings_codec.h"

namespace isocorr::api {

// One line per field in both directions, so adding a setting is a two-line change here.
#define ISOCORR_SETTINGS_FIELDS(X)                          \
  X(level0_samples, s.level0_samples)                       \
  X(level0_extra_targets, s.level0_extra_targets)           \
  X(max_level0_diso, s.max_level0_diso)                     \
  X(max_level0_maps, s.max_level0_maps)                     \
  X(min_tracked, s.min_tracked)                             \
  X(max_tracked, s.max_tracked)                             \
  X(orientation_threshold, s.orientation_threshold)         \
  X(orientation_margin, s.orientation_margin)               \
  X(orientation_weight, s.orientation_weight)               \
  X(handedness_guard, s.tracking.handedness_guard)          \
  X(anchor_cap, s.tracking.anchor_cap)                      \
  X(trim_fraction, s.tracking.trim_fraction)                \
  X(window_factor, s.tracking.window_factor)                \
  X(dense_anchors, s.dense.anchor_count)                    \
  X(dense_outliers, s.dense.outlier_fraction)               \
  X(dense_outlier_ratio, s.dense.outlier_ratio)             \
  X(dense_locality, s.dense.locality)                       \
  X(level0_radius, s.preprocess.level0_radius)              \
  X(level_shrink, s.preprocess.level_shrink)                \
  X(decision_level, s.preprocess.decision_level)            \
  X(agd_sources, s.preprocess.saliency.agd_sources)         \
  X(extremity_radius, s.preprocess.saliency.extremity_radius)

MatchSettings settings_from_proto(const v1::MatchSettings& p) {
  MatchSettings s;
#define ISOCORR_FROM_PROTO(field, member) \
  if (p.has_##field()) member = static_cast<decltype(member)>(p.field());
  ISOCORR_SETTINGS_FIELDS(ISOCORR_FROM_PROTO)
#undef ISOCORR_FROM_PROTO
  if (p.selection() == v1::MatchSettings::LEAST_DISTORTION) s.selection = SelectionRule::kLeastDistortion;
  return s;
}

v1::MatchSettings settings_to_proto(const MatchSettings& s) {
  v1::MatchSettings p;
#define ISOCORR_TO_PROTO(field, member) p.set_##field(member);
  ISOCORR_SETTINGS_FIELDS(ISOCORR_TO_PROTO)
#undef ISOCORR_TO_PROTO
  p.set_selection(s.selection == SelectionRule::kLeastDistortion ? v1::MatchSettings::LEAST_DISTORTION
                                                                 : v1::MatchSettings::ORIENTATION_THEN_DISTORTION);
  return p;
}

}  // namespace isocorr::api

// The one entry point for a whole match: both shapes preprocessed (or taken from whoever
// already has them), matched, and the result with its report. The CLI, the server's
// workers and the benchmark all call run_match; they differ only in their ShapeProvider.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "isocorr/output/match_result.h"
#include "isocorr/settings/match_settings.h"
#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr {

enum class ShapeRole { kSource, kTarget };

// Hands the pipeline the preprocessed shape of one side. The server's provider reads the
// mesh store and its shape cache; MeshPairShapes below builds from meshes in memory.
class ShapeProvider {
 public:
  virtual ~ShapeProvider() = default;
  // The shape of `role` preprocessed with `options`. Throws InputError for an unusable
  // mesh and Cancelled when `control` asks; may block while another caller builds it.
  // run_match asks for both roles from two threads at once.
  virtual std::shared_ptr<const PreprocessedShape> shape(ShapeRole role, const PreprocessOptions& options,
                                                         const JobControl& control) = 0;
};

// Two meshes in memory, each preprocessed once per distinct option set, so a caller that
// matches the same pair under several settings (the benchmark) preprocesses once.
class MeshPairShapes : public ShapeProvider {
 public:
  MeshPairShapes(const TriangleMesh& source, const TriangleMesh& target) : source_(source), target_(target) {}
  std::shared_ptr<const PreprocessedShape> shape(ShapeRole role, const PreprocessOptions& options,
                                                 const JobControl& control) override;

 private:
  const TriangleMesh& source_;
  const TriangleMesh& target_;
  std::mutex mutex_;  // guards built_
  std::map<std::string, std::shared_ptr<const PreprocessedShape>> built_;  // by role and options key
};

// Validates `settings`, gets both shapes (progress stages "preprocess-source" and
// "preprocess-target", then the match's own), matches them and writes the report into
// `result.output.report_json`. The timings include the time spent getting the shapes.
MatchResult run_match(ShapeProvider& shapes, const MatchSettings& settings, const JobControl& control = {});

// The same for two meshes in memory.
MatchResult match_meshes(const TriangleMesh& source, const TriangleMesh& target, const MatchSettings& settings,
                         const JobControl& control = {});

}  // namespace isocorr

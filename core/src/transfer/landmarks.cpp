#include "isocorr/transfer/landmarks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "isocorr/util/error.h"

namespace isocorr {
namespace {

std::string out_of_range(const char* side, int vertex, int count) {
  return std::string(side) + " vertex " + std::to_string(vertex) + " is out of range: the " + side + " mesh has " +
         std::to_string(count) + " vertices";
}

}  // namespace

std::optional<LandmarkProblem> find_landmark_problem(const std::vector<Landmark>& landmarks, int source_vertices,
                                                     int target_vertices) {
  if (landmarks.size() > kMaxLandmarks)
    return LandmarkProblem{kMaxLandmarks, "more than " + std::to_string(kMaxLandmarks) + " landmarks", {}};
  std::map<int, size_t> by_source, by_target;  // vertex -> first entry naming it
  for (size_t i = 0; i < landmarks.size(); ++i) {
    const Landmark& l = landmarks[i];
    auto problem = [i](const std::string& message, std::optional<size_t> earlier = std::nullopt) {
      return LandmarkProblem{i, message, earlier};
    };
    if (l.source_vertex < 0) return problem("source vertex " + std::to_string(l.source_vertex) + " is negative");
    if (l.target_vertex < 0) return problem("target vertex " + std::to_string(l.target_vertex) + " is negative");
    if (source_vertices >= 0 && l.source_vertex >= source_vertices)
      return problem(out_of_range("source", l.source_vertex, source_vertices));
    if (target_vertices >= 0 && l.target_vertex >= target_vertices)
      return problem(out_of_range("target", l.target_vertex, target_vertices));
    // "source vertex 1 is given two targets, 2 and 5": `earlier` named the vertex first.
    auto two_partners = [&](const char* side, int vertex, const char* partners, int first, int second,
                            size_t earlier) {
      return problem(std::string(side) + " vertex " + std::to_string(vertex) + " is given two " + partners + ", " +
                         std::to_string(first) + " and " + std::to_string(second),
                     earlier);
    };
    const auto source_seen = by_source.find(l.source_vertex);
    const auto target_seen = by_target.find(l.target_vertex);
    if (source_seen != by_source.end() && landmarks[source_seen->second] == l)
      return problem("the pair " + std::to_string(l.source_vertex) + " " + std::to_string(l.target_vertex) +
                         " is given twice",
                     source_seen->second);
    if (source_seen != by_source.end())
      return two_partners("source", l.source_vertex, "targets", landmarks[source_seen->second].target_vertex,
                          l.target_vertex, source_seen->second);
    if (target_seen != by_target.end())
      return two_partners("target", l.target_vertex, "sources", landmarks[target_seen->second].source_vertex,
                          l.source_vertex, target_seen->second);
    by_source.emplace(l.source_vertex, i);
    by_target.emplace(l.target_vertex, i);
  }
  return std::nullopt;
}

void validate_landmarks(const std::vector<Landmark>& landmarks, int source_vertices, int target_vertices) {
  if (const auto problem = find_landmark_problem(landmarks, source_vertices, target_vertices))
    throw InputError("landmarks[" + std::to_string(problem->index) + "]: " + problem->message +
                     (problem->earlier ? " (landmarks[" + std::to_string(*problem->earlier) + "])" : ""));
}

LandmarkGeometry::LandmarkGeometry(const PreprocessedShape& source, const PreprocessedShape& target,
                                   const std::vector<Landmark>& in_files) {
  auto field = [](const PreprocessedShape& shape, int vertex) {
    std::vector<float> distances = shape.geodesics().distance_field(vertex);
    const float scale = static_cast<float>(1.0 / shape.diameter());
    for (float& d : distances) d *= scale;
    return distances;
  };
  for (const Landmark& l : in_files) {
    const int s = source.clean().input_to_clean.at(l.source_vertex);
    const int t = target.clean().input_to_clean.at(l.target_vertex);
    // Welded input vertices share a clean vertex: the first landmark naming it counts.
    const bool seen = std::any_of(pairs_.begin(), pairs_.end(),
                                  [&](const std::pair<int, int>& p) { return p.first == s || p.second == t; });
    if (seen) continue;
    pairs_.emplace_back(s, t);
    source_fields_.push_back(field(source, s));
    target_fields_.push_back(field(target, t));
  }
}

double LandmarkGeometry::disagreement(const std::vector<std::pair<int, int>>& vertex_pairs) const {
  if (pairs_.empty() || vertex_pairs.empty()) return 0;
  double sum = 0;
  for (size_t l = 0; l < pairs_.size(); ++l)
    for (const auto& [a, b] : vertex_pairs) sum += std::abs(source_fields_[l][a] - target_fields_[l][b]);
  return sum / (static_cast<double>(pairs_.size()) * vertex_pairs.size());
}

std::vector<double> LandmarkGeometry::errors(const std::vector<int>& forward) const {
  std::vector<double> out;
  for (size_t l = 0; l < pairs_.size(); ++l) out.push_back(target_fields_[l][forward[pairs_[l].first]]);
  return out;
}

double LandmarkGeometry::largest_error(const std::vector<int>& forward) const {
  const std::vector<double> all = errors(forward);
  return all.empty() ? 0.0 : *std::max_element(all.begin(), all.end());
}

void pin_landmarks(const LandmarkGeometry& landmarks, std::vector<int>& forward, std::vector<int>& reverse) {
  for (const auto& [s, t] : landmarks.pairs()) {
    forward[s] = t;
    reverse[t] = s;
  }
}

void hold_landmarks(const LandmarkGeometry& landmarks, DenseMap& dense, MatchResult& result) {
  if (landmarks.empty()) return;
  LandmarkDiagnostics& diagnostics = result.diagnostics.landmarks;
  diagnostics.count = landmarks.size();
  diagnostics.chosen_errors = landmarks.errors(dense.forward);
  diagnostics.honoured = landmarks.largest_error(dense.forward) <= kLandmarkTolerance;
  if (!diagnostics.honoured) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "landmarks: the chosen map sent a landmark %.3f of the diameter from its partner (tolerance "
                  "%.2f); each landmark was then sent to its partner",
                  landmarks.largest_error(dense.forward), kLandmarkTolerance);
    result.messages.warnings.push_back(text);
  }
  pin_landmarks(landmarks, dense.forward, dense.reverse);
}

}  // namespace isocorr

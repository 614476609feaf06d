#include "storage/result_parts.h"

#include <stdexcept>

#include "isocorr/output/map_files.h"
#include "isocorr/settings/settings_json.h"
#include "isocorr/util/sha256.h"

namespace isocorr::server {
using nlohmann::json;

namespace {

template <typename T>
std::string to_bytes(const std::vector<T>& values) {  // little-endian hosts only (x86-64, arm64)
  std::string bytes(values.size() * sizeof(T), '\0');
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

json manifest_of(const std::map<ResultPart, std::string>& parts, size_t source_vertices, size_t target_vertices) {
  json entries = json::object();
  for (const auto& [part, bytes] : parts)
    entries[std::string(result_part_name(part))] = {{"bytes", bytes.size()}, {"sha256", sha256_hex(bytes)}};
  return {{"source_vertices", source_vertices}, {"target_vertices", target_vertices}, {"parts", entries}};
}

std::string settings_digest(const MatchSettings& settings) { return sha256_hex(settings_to_json(settings).dump()); }

}  // namespace

void bind_manifest(json& manifest, const JobRecord& job) {
  manifest["job"] = {{"id", job.id},
                     {"source", job.source_digest},
                     {"target", job.target_digest},
                     {"settings_sha256", settings_digest(job.settings)}};
}

std::string result_binding_problem(const json& manifest, const JobRecord& job) {
  if (!manifest.contains("job")) return "its manifest names no job";
  const json& made_for = manifest.at("job");
  if (made_for.value("id", "") != job.id) return "it was made for jobs/" + made_for.value("id", "?");
  if (made_for.value("source", "") != job.source_digest || made_for.value("target", "") != job.target_digest)
    return "it was made from other meshes";
  if (made_for.value("settings_sha256", "") != settings_digest(job.settings)) return "it was made with other settings";
  return "";
}

EncodedResult encode_result(const JobRecord& job, const MatchOutput& result) {
  EncodedResult encoded;
  encoded.parts[ResultPart::kForwardMap] = to_bytes(result.forward);
  encoded.parts[ResultPart::kReverseMap] = to_bytes(result.reverse);
  encoded.parts[ResultPart::kForwardConfidence] = to_bytes(result.forward_confidence);
  encoded.parts[ResultPart::kReverseConfidence] = to_bytes(result.reverse_confidence);
  encoded.parts[ResultPart::kReport] = result.report_json;
  static_assert(sizeof(SurfacePoint) == 16, "a stored point is an int32 face and three float32 weights");
  // A result without precise maps is stored as those from before them were.
  if (!result.forward_precise.empty()) encoded.parts[ResultPart::kForwardPrecise] = to_bytes(result.forward_precise);
  if (!result.reverse_precise.empty()) encoded.parts[ResultPart::kReversePrecise] = to_bytes(result.reverse_precise);
  encoded.manifest = manifest_of(encoded.parts, result.forward.size(), result.reverse.size());
  bind_manifest(encoded.manifest, job);
  return encoded;
}

json manifest_of_unchecked_parts(const JobRecord& job, const std::map<ResultPart, std::string>& bytes) {
  const std::string& forward_bytes = bytes.at(ResultPart::kForwardMap);
  const std::string& reverse_bytes = bytes.at(ResultPart::kReverseMap);
  const std::vector<int> forward = values_from_bytes<int>(forward_bytes);
  const std::vector<int> reverse = values_from_bytes<int>(reverse_bytes);
  // Without digests only the structure can be checked: whole int32/float32 arrays, one
  // confidence per map entry, every index inside the other map's length.
  bool whole = forward.size() * sizeof(int) == forward_bytes.size() &&
               reverse.size() * sizeof(int) == reverse_bytes.size() &&
               bytes.at(ResultPart::kForwardConfidence).size() == forward.size() * sizeof(float) &&
               bytes.at(ResultPart::kReverseConfidence).size() == reverse.size() * sizeof(float);
  for (const int index : forward) whole = whole && index >= 0 && index < static_cast<int64_t>(reverse.size());
  for (const int index : reverse) whole = whole && index >= 0 && index < static_cast<int64_t>(forward.size());
  if (!whole) throw std::runtime_error("its parts do not fit together");
  json manifest = manifest_of(bytes, forward.size(), reverse.size());
  bind_manifest(manifest, job);
  return manifest;
}

bool manifest_holds(const json& manifest, ResultPart part) {
  return manifest.contains("parts") && manifest.at("parts").contains(std::string(result_part_name(part)));
}

PartNotStored::PartNotStored(const std::string& job_id, ResultPart part)
    : ServiceError(Kind::kNotFound, "the result of jobs/" + job_id + " was stored before it had the part " +
                                        std::string(result_part_name(part)) + "; run the job again to get it") {}

std::string result_part_problem(const json& manifest, ResultPart part, const std::string& bytes) {
  const std::string name(result_part_name(part));
  const json& expected = manifest.at("parts").at(name);
  if (bytes.size() != expected.at("bytes").get<size_t>())
    return name + " has " + std::to_string(bytes.size()) + " bytes, not " +
           std::to_string(expected.at("bytes").get<size_t>());
  if (sha256_hex(bytes) != expected.at("sha256").get<std::string>()) return name + " does not match its sha256";
  if (part == ResultPart::kForwardMap || part == ResultPart::kReverseMap) {
    const bool forward = part == ResultPart::kForwardMap;
    const auto count = manifest.at(forward ? "source_vertices" : "target_vertices").get<size_t>();
    const auto limit = manifest.at(forward ? "target_vertices" : "source_vertices").get<int64_t>();
    const std::vector<int> map = values_from_bytes<int>(bytes);
    if (map.size() != count || bytes.size() % sizeof(int) != 0)
      return name + " has " + std::to_string(map.size()) + " entries for " + std::to_string(count) + " vertices";
    // A part's reverse map marks target vertices without counterpart (method = part).
    for (const int index : map)
      if (index >= limit || (index < 0 && (forward || index != kNoCounterpart)))
        return name + " holds index " + std::to_string(index) + ", outside the other mesh's " +
               std::to_string(limit) + " vertices";
  }
  if (part == ResultPart::kForwardPrecise || part == ResultPart::kReversePrecise) {
    const auto count = manifest.at(part == ResultPart::kForwardPrecise ? "source_vertices" : "target_vertices").get<size_t>();
    if (bytes.size() != count * sizeof(SurfacePoint))
      return name + " has " + std::to_string(bytes.size()) + " bytes for " + std::to_string(count) + " vertices";
  }
  return "";
}

}  // namespace isocorr::server

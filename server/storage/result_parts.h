// A finished job's result as any store keeps it: one byte string per part (little-endian
// int32 maps, float32 confidence, the JSON report, precise maps as an int32 face and three
// float32 weights per point) and a manifest of each part's length
// and SHA-256 with both meshes' vertex counts, so that every read can be checked. The
// manifest also names the job it was made for (its id, both meshes' digests and the
// settings' digest), so that a result moved to another job's place is not served there.
#pragma once

#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "isocorr/output/match_output.h"
#include "service_error.h"
#include "storage/job_record.h"

namespace isocorr::server {

struct EncodedResult {
  std::map<ResultPart, std::string> parts;
  nlohmann::json manifest;
};

EncodedResult encode_result(const JobRecord& job, const MatchOutput& result);
// The manifest of parts whose digests were never recorded (results from before manifests),
// bound to `job`, after checking their structure (whole arrays, one confidence per map
// entry, indices inside the other map). Throws std::runtime_error when they do not fit.
nlohmann::json manifest_of_unchecked_parts(const JobRecord& job, const std::map<ResultPart, std::string>& parts);
// Adds `job` to a manifest written before manifests named their job.
void bind_manifest(nlohmann::json& manifest, const JobRecord& job);

// Why `manifest` was not made for `job` (another job, other meshes or other settings, or
// no job named); empty when it was.
std::string result_binding_problem(const nlohmann::json& manifest, const JobRecord& job);

// What is wrong with `bytes` as `part` of the result `manifest` describes (length, SHA-256,
// a map's entry count and index range); empty when nothing is. Throws
// nlohmann::json::exception for a manifest that lacks what it needs.
std::string result_part_problem(const nlohmann::json& manifest, ResultPart part, const std::string& bytes);

// Whether the result `manifest` describes has `part`: results stored before precise maps
// lack them.
bool manifest_holds(const nlohmann::json& manifest, ResultPart part);

// A part the job's result does not have (it was stored before the part existed): NOT_FOUND,
// and the result is left as it is.
class PartNotStored : public ServiceError {
 public:
  PartNotStored(const std::string& job_id, ResultPart part);
};

template <typename T>
std::vector<T> values_from_bytes(const std::string& bytes) {  // little-endian hosts only (x86-64, arm64)
  std::vector<T> values(bytes.size() / sizeof(T));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(T));
  return values;
}

// Reading a stored result back for the job asking, part by part, each part checked against
// the manifest and the manifest against the job. A result that fails is set aside by the
// store; it and a missing result throw ServiceError(kDataLoss).
class ResultReader {
 public:
  virtual ~ResultReader() = default;
  std::vector<int> read_map(const JobRecord& job, ResultPart part) const {  // kForwardMap, kReverseMap
    return values_from_bytes<int>(read_checked_part(job, part));
  }
  std::vector<float> read_confidence(const JobRecord& job, ResultPart part) const {  // k*Confidence
    return values_from_bytes<float>(read_checked_part(job, part));
  }
  std::string read_report(const JobRecord& job) const { return read_checked_part(job, ResultPart::kReport); }
  PreciseMap read_precise(const JobRecord& job, ResultPart part) const {  // k*Precise
    return values_from_bytes<SurfacePoint>(read_checked_part(job, part));
  }

 protected:
  // The part's bytes after the checks of result_binding_problem and result_part_problem.
  virtual std::string read_checked_part(const JobRecord& job, ResultPart part) const = 0;
};

}  // namespace isocorr::server

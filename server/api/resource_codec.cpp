#include "api/resource_codec.h"

#include "codec/settings_codec.h"
#include "isocorr/util/sha256.h"

namespace isocorr::server {
namespace {

void set_time(google::protobuf::Timestamp* timestamp, int64_t ms) {
  timestamp->set_seconds(ms / 1000);
  timestamp->set_nanos(static_cast<int32_t>(ms % 1000) * 1000000);
}

std::string suffix_after(const std::string& name, const std::string& collection) {
  if (name.rfind(collection, 0) != 0 || name.size() == collection.size()) return {};
  const std::string rest = name.substr(collection.size());
  return rest.find('/') == std::string::npos ? rest : std::string();
}

v1::Job::State state_to_proto(JobState state) {
  switch (state) {
    case JobState::kQueued: return v1::Job::QUEUED;
    case JobState::kRunning: return v1::Job::RUNNING;
    case JobState::kSucceeded: return v1::Job::SUCCEEDED;
    case JobState::kFailed: return v1::Job::FAILED;
    case JobState::kCancelled: return v1::Job::CANCELLED;
  }
  return v1::Job::STATE_UNSPECIFIED;
}

}  // namespace

v1::Mesh mesh_to_proto(const MeshInfo& info, ShapeCache::MeshState state) {
  v1::Mesh mesh;
  mesh.set_name("meshes/" + info.digest);
  mesh.set_sha256(info.digest);
  mesh.set_filename(info.filename);
  mesh.set_size_bytes(info.size_bytes);
  mesh.set_format(info.format);
  mesh.set_vertex_count(info.vertex_count);
  mesh.set_face_count(info.face_count);
  for (const auto& note : info.notes) mesh.add_notes(note);
  set_time(mesh.mutable_create_time(), info.create_time_ms);
  mesh.set_preprocessing_state(state == ShapeCache::MeshState::kReady      ? v1::Mesh::PREPROCESSED
                               : state == ShapeCache::MeshState::kBuilding ? v1::Mesh::PREPROCESSING
                                                                           : v1::Mesh::NOT_PREPROCESSED);
  return mesh;
}

v1::Job job_to_proto(const JobRecord& job) {
  v1::Job proto;
  proto.set_name("jobs/" + job.id);
  proto.set_state(state_to_proto(job.state));
  proto.set_done(is_final(job.state));
  proto.set_source_mesh("meshes/" + job.source_digest);
  proto.set_target_mesh("meshes/" + job.target_digest);
  *proto.mutable_settings() = api::settings_to_proto(job.settings);
  v1::JobProgress* progress = proto.mutable_progress();
  progress->set_stage(job.progress.stage);
  progress->set_level(job.progress.level);
  progress->set_levels(job.progress.levels);
  progress->set_percent(100 * job.progress.fraction);
  set_time(proto.mutable_create_time(), job.create_time_ms);
  if (job.start_time_ms) set_time(proto.mutable_start_time(), job.start_time_ms);
  if (job.end_time_ms && is_final(job.state)) set_time(proto.mutable_end_time(), job.end_time_ms);
  proto.set_attempts(job.attempts);
  if (job.state == JobState::kSucceeded) {
    const MatchSummary& s = job.summary;
    v1::MatchSummary* result = proto.mutable_result();
    result->set_source_vertex_count(s.source_vertices);
    result->set_target_vertex_count(s.target_vertices);
    result->set_diso(s.diso);
    result->set_diso_max(s.diso_max);
    result->set_dense_orientation(s.dense_orientation);
    result->set_level0_map_count(s.level0_maps);
    result->set_tracked_map_count(s.tracked_maps);
    result->set_chosen_level0_rank(s.chosen_level0_rank);
    for (const auto& t : s.timings) {
      v1::StageTiming* timing = result->add_timings();
      timing->set_stage(t.stage);
      timing->mutable_duration()->set_seconds(static_cast<int64_t>(t.seconds));
      timing->mutable_duration()->set_nanos(static_cast<int32_t>((t.seconds - static_cast<int64_t>(t.seconds)) * 1e9));
    }
    for (const auto& note : s.notes) result->add_notes(note);
    result->set_verdict(s.verdict);
    for (const auto& reason : s.verdict_reasons) result->add_verdict_reasons(reason);
  } else if (job.state == JobState::kFailed || job.state == JobState::kCancelled) {
    proto.mutable_error()->set_code(static_cast<int>(job.error_code));
    proto.mutable_error()->set_message(job.error_message);
  }
  return proto;
}

std::string mesh_digest_from_name(const std::string& name) {
  const std::string digest = suffix_after(name, "meshes/");
  return is_sha256_hex(digest) ? digest : std::string();
}
std::string job_id_from_name(const std::string& name) { return suffix_after(name, "jobs/"); }

}  // namespace isocorr::server

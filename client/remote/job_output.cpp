#include "remote/job_output.h"

#include <google/protobuf/util/json_util.h>
#include <spdlog/fmt/fmt.h>

#include <grpcpp/support/status.h>

#include "commands.h"

namespace isocorr::cli {

std::string to_json(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  options.always_print_primitive_fields = true;  // `done: false` is information
  std::string json;
  (void)google::protobuf::util::MessageToJsonString(message, &json, options);
  return json;
}

std::string describe_job(const v1::Job& job) {
  std::string line = fmt::format("{}  {}", job.name(), v1::Job::State_Name(job.state()));
  if (job.state() == v1::Job::RUNNING)
    line += fmt::format("  {} level {}/{} {:.0f}%", job.progress().stage(), job.progress().level(),
                        job.progress().levels(), job.progress().percent());
  if (job.has_result())
    line += fmt::format("  D_iso {:.4f}, {} -> {} vertices", job.result().diso(), job.result().source_vertex_count(),
                        job.result().target_vertex_count());
  if (job.has_error()) line += "  " + job.error().message();
  return line;
}

std::string describe_mesh(const v1::Mesh& mesh) {
  return fmt::format("{}  {}  {} vertices, {} faces, {} bytes, {}", mesh.name(), mesh.filename(), mesh.vertex_count(),
                     mesh.face_count(), mesh.size_bytes(), v1::Mesh::PreprocessingState_Name(mesh.preprocessing_state()));
}

Progress progress_of(const v1::Job& job) {
  Progress progress;
  progress.stage = job.done() ? "done" : job.progress().stage();
  progress.level = job.progress().level();
  progress.levels = job.progress().levels();
  progress.fraction = job.done() ? 1.0 : job.progress().percent() / 100;
  return progress;
}

int exit_code_for_job(const v1::Job& job) {
  switch (job.state()) {
    case v1::Job::SUCCEEDED: return kExitOk;
    case v1::Job::CANCELLED: return kExitCancelled;
    case v1::Job::FAILED:
      return job.error().code() == static_cast<int>(grpc::StatusCode::INVALID_ARGUMENT) ? kExitBadInput : kExitFailure;
    default: return kExitNotDone;
  }
}

}  // namespace isocorr::cli

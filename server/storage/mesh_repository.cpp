#include "storage/mesh_repository.h"

#include <nlohmann/json.hpp>

#include "isocorr/mesh/mesh_cleaning.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"
#include "service_error.h"
#include "storage/job_record.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;

namespace {

std::string too_large(int64_t limit) {
  return "mesh larger than the server's limit of " + std::to_string(limit) +
         " bytes (isocorr-server --max-mesh-bytes)";
}

}  // namespace

nlohmann::json mesh_info_to_json(const MeshInfo& info) {
  return {{"digest", info.digest},         {"filename", info.filename},         {"size_bytes", info.size_bytes},
          {"format", info.format},         {"vertex_count", info.vertex_count}, {"face_count", info.face_count},
          {"notes", info.notes},           {"create_time_ms", info.create_time_ms}};
}

MeshInfo mesh_info_from_json(const nlohmann::json& j) {
  MeshInfo info;
  info.digest = j.at("digest");
  info.filename = j.at("filename");
  info.size_bytes = j.at("size_bytes");
  info.format = j.at("format");
  info.vertex_count = j.at("vertex_count");
  info.face_count = j.at("face_count");
  info.notes = j.at("notes").get<std::vector<std::string>>();
  info.create_time_ms = j.at("create_time_ms");
  return info;
}

std::string corrupted_mesh_message(const std::string& digest) {
  return "mesh meshes/" + digest +
         " is corrupted on the server's disk and was set aside; upload the same file again to repair it";
}

void MeshRepository::check_upload_header(const std::string& digest, int64_t declared_size) const {
  if (!is_sha256_hex(digest))
    throw ServiceError(Kind::kInvalidArgument, "sha256 must be 64 lower-case hex characters, got '" + digest + "'");
  if (declared_size > max_mesh_bytes()) throw ServiceError(Kind::kResourceExhausted, too_large(max_mesh_bytes()));
}

MeshUpload::MeshUpload(std::string digest, std::string filename, int64_t max_bytes)
    : digest_(std::move(digest)), filename_(std::move(filename)), max_bytes_(max_bytes) {}

void MeshUpload::append(std::string_view bytes) {
  received_ += static_cast<int64_t>(bytes.size());
  if (received_ > max_bytes_) throw ServiceError(Kind::kResourceExhausted, too_large(max_bytes_));
  hasher_.update(bytes);
  keep(bytes);
}

MeshInfo MeshUpload::commit() {
  const std::string actual = hasher_.hex_digest();
  if (actual != digest_)
    throw ServiceError(Kind::kInvalidArgument, "content hashes to sha256 " + actual + ", not " + digest_ +
                                                   " as the upload header says (corrupted or truncated upload)");
  const std::string bytes = kept_bytes();
  MeshInfo info;
  try {
    const LoadedMesh loaded = parse_mesh(bytes, filename_);
    // What every job checks, with the default cleaning: an accepted upload can be matched
    // unless a job's own cleaning settings are stricter.
    const CleanMesh clean = clean_mesh(loaded.mesh);
    check_matchable(clean);
    info.format = loaded.format;
    info.vertex_count = loaded.mesh.num_vertices();
    info.face_count = loaded.mesh.num_faces();
    info.notes = loaded.notes;
    for (const auto& repair : clean.repairs) info.notes.push_back("cleaning: " + repair);
  } catch (const InputError& e) {
    throw ServiceError(Kind::kInvalidArgument, "not a usable mesh: " + std::string(e.what()));
  }
  info.digest = digest_;
  info.filename = filename_;
  info.size_bytes = received_;
  info.create_time_ms = now_ms();
  return store(info);
}

}  // namespace isocorr::server

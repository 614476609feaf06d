#include "storage/mesh_store.h"

#include <algorithm>
#include <chrono>
#include <random>

#include <nlohmann/json.hpp>

#include "isocorr/mesh/mesh_cleaning.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"
#include "service_error.h"
#include "storage/durable_file.h"

namespace isocorr::server {
namespace fs = std::filesystem;
using Kind = ServiceError::Kind;

namespace {

int64_t now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string random_suffix() {
  static std::mutex mutex;
  static std::mt19937_64 generator{std::random_device{}()};
  std::lock_guard lock(mutex);
  return std::to_string(generator());
}

nlohmann::json to_json(const MeshInfo& info) {
  return {{"digest", info.digest},         {"filename", info.filename},         {"size_bytes", info.size_bytes},
          {"format", info.format},         {"vertex_count", info.vertex_count}, {"face_count", info.face_count},
          {"notes", info.notes},           {"create_time_ms", info.create_time_ms}};
}

MeshInfo from_json(const nlohmann::json& j) {
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

std::string too_large(int64_t limit) {
  return "mesh larger than the server's limit of " + std::to_string(limit) +
         " bytes (isocorr-server --max-mesh-bytes)";
}

}  // namespace

MeshStore::MeshStore(const fs::path& data_dir, int64_t max_mesh_bytes)
    : dir_(data_dir / "meshes"), temp_dir_(data_dir / "tmp"), max_mesh_bytes_(max_mesh_bytes) {
  fs::create_directories(dir_);
  fs::remove_all(temp_dir_);  // uploads that were never acknowledged
  fs::create_directories(temp_dir_);
}

std::unique_ptr<MeshUpload> MeshStore::begin_upload(const std::string& digest, const std::string& filename,
                                                    int64_t declared_size) {
  if (!is_sha256_hex(digest))
    throw ServiceError(Kind::kInvalidArgument, "sha256 must be 64 lower-case hex characters, got '" + digest + "'");
  if (declared_size > max_mesh_bytes_) throw ServiceError(Kind::kResourceExhausted, too_large(max_mesh_bytes_));
  const fs::path temp = temp_dir_ / (digest + "." + random_suffix());
  return std::unique_ptr<MeshUpload>(new MeshUpload(*this, digest, filename, temp));
}

MeshUpload::MeshUpload(MeshStore& store, std::string digest, std::string filename, fs::path temp)
    : store_(store), digest_(std::move(digest)), filename_(std::move(filename)), temp_(std::move(temp)),
      file_(std::fopen(temp_.c_str(), "wb"), &std::fclose) {
  if (!file_) throw std::runtime_error("cannot create '" + temp_.string() + "'");
}

MeshUpload::~MeshUpload() {
  file_.reset();
  std::error_code ignored;
  fs::remove(temp_, ignored);
}

void MeshUpload::append(std::string_view bytes) {
  received_ += static_cast<int64_t>(bytes.size());
  if (received_ > store_.max_mesh_bytes_) throw ServiceError(Kind::kResourceExhausted, too_large(store_.max_mesh_bytes_));
  hasher_.update(bytes);
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_.get()) != bytes.size())
    throw std::runtime_error("cannot write '" + temp_.string() + "'");
}

MeshInfo MeshUpload::commit() {
  const std::string actual = hasher_.hex_digest();
  if (actual != digest_)
    throw ServiceError(Kind::kInvalidArgument, "content hashes to sha256 " + actual + ", not " + digest_ +
                                                   " as the upload header says (corrupted or truncated upload)");
  if (std::fflush(file_.get()) != 0) throw std::runtime_error("cannot write '" + temp_.string() + "'");
  file_.reset();

  MeshInfo info;
  try {
    const LoadedMesh loaded = parse_mesh(read_whole_file(temp_), filename_);
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

  std::lock_guard lock(store_.mutex_);
  if (auto existing = store_.get(digest_)) return *existing;  // a concurrent upload won
  fsync_path(temp_);
  fs::rename(temp_, store_.mesh_path(digest_));
  fsync_path(store_.dir_);
  write_file_durably(store_.info_path(digest_), to_json(info).dump());
  return info;
}

std::optional<MeshInfo> MeshStore::get(const std::string& digest) const {
  if (!is_sha256_hex(digest)) return std::nullopt;
  std::error_code error;
  if (!fs::exists(info_path(digest), error)) return std::nullopt;
  try {
    return from_json(nlohmann::json::parse(read_whole_file(info_path(digest))));
  } catch (const std::exception&) {
    return std::nullopt;  // removed concurrently
  }
}

std::vector<MeshInfo> MeshStore::list() const {
  std::vector<std::string> digests;
  for (const auto& entry : fs::directory_iterator(dir_))
    if (entry.path().extension() == ".json") digests.push_back(entry.path().stem().string());
  std::sort(digests.begin(), digests.end());
  std::vector<MeshInfo> meshes;
  for (const auto& digest : digests)
    if (auto info = get(digest)) meshes.push_back(std::move(*info));
  return meshes;
}

bool MeshStore::remove(const std::string& digest) {
  std::lock_guard lock(mutex_);
  if (!get(digest)) return false;
  fs::remove(info_path(digest));  // the mesh is gone once its description is
  fsync_path(dir_);
  fs::remove(mesh_path(digest));
  return true;
}

std::string MeshStore::read_bytes(const std::string& digest) const {
  if (!get(digest)) throw ServiceError(Kind::kNotFound, "no mesh meshes/" + digest + " on this server; upload it first");
  return read_whole_file(mesh_path(digest));
}

}  // namespace isocorr::server

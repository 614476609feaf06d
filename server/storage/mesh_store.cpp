#include "storage/mesh_store.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <random>

#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include "isocorr/mesh/mesh_cleaning.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"
#include "service_error.h"
#include "storage/durable_file.h"
#include "storage/sealed_json.h"
#include "storage/storage_failure.h"

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


// Told when a stored mesh is found corrupted, and every time it is asked for afterwards.
std::string corrupted_message(const std::string& digest) {
  return "mesh meshes/" + digest +
         " is corrupted on the server's disk and was set aside; upload the same file again to repair it";
}

std::string too_large(int64_t limit) {
  return "mesh larger than the server's limit of " + std::to_string(limit) +
         " bytes (isocorr-server --max-mesh-bytes)";
}

}  // namespace

MeshStore::MeshStore(const fs::path& data_dir, int64_t max_mesh_bytes)
    : dir_(data_dir / "meshes"), temp_dir_(data_dir / "tmp"), quarantine_(data_dir), max_mesh_bytes_(max_mesh_bytes) {
  fs::create_directories(dir_);
  fs::remove_all(temp_dir_);  // uploads that were never acknowledged
  fs::create_directories(temp_dir_);
  remove_leftovers();
}

void MeshStore::remove_leftovers() {
  // A commit interrupted by a crash or a full disk: .json.tmp files, and .mesh files whose
  // description never reached the disk (never acknowledged).
  for (const auto& entry : fs::directory_iterator(dir_)) {
    const fs::path& path = entry.path();
    const bool unacknowledged = path.extension() == ".tmp" ||
                                (path.extension() == ".mesh" && !fs::exists(info_path(path.stem().string())));
    if (!unacknowledged) continue;
    spdlog::info("storage: removing {} left by an unfinished upload", path.string());
    fs::remove(path);
  }
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
  if (!file_) throw_write_failure("cannot create", temp_, errno);
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
    throw_write_failure("cannot write", temp_, errno);
}

MeshInfo MeshUpload::commit() {
  const std::string actual = hasher_.hex_digest();
  if (actual != digest_)
    throw ServiceError(Kind::kInvalidArgument, "content hashes to sha256 " + actual + ", not " + digest_ +
                                                   " as the upload header says (corrupted or truncated upload)");
  if (std::fflush(file_.get()) != 0) throw_write_failure("cannot write", temp_, errno);
  if (std::fclose(file_.release()) != 0) throw_write_failure("cannot write", temp_, errno);

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
  // A concurrent upload won; a corrupted copy is quarantined (and replaced below).
  MeshStore::Lookup existing = store_.quarantine_if_corrupted(digest_, /*with_bytes=*/true);
  if (existing.found == MeshStore::Found::kIntact) return existing.info;
  const fs::path mesh_path = store_.mesh_path(digest_);
  try {
    fsync_path(temp_);
    guard_storage_write("cannot store", mesh_path, [&] { fs::rename(temp_, mesh_path); });
    fsync_path(store_.dir_);
    write_file_durably(store_.info_path(digest_), seal_json(to_json(info)));
  } catch (...) {
    std::error_code ignored;  // not acknowledged: nothing may stay behind
    fs::remove(mesh_path, ignored);
    throw;
  }
  if (existing.found == MeshStore::Found::kQuarantined) {  // repaired: no longer reported lost
    for (const char* extension : {".mesh", ".json"}) store_.quarantine_.archive("meshes", digest_ + extension);
    spdlog::info("storage: mesh {} repaired by a new upload", digest_);
  }
  return info;
}

MeshStore::Lookup MeshStore::lookup(const std::string& digest, bool with_bytes) const {
  Lookup result;
  if (!is_sha256_hex(digest)) return result;
  std::string text;
  try {
    text = read_whole_file(info_path(digest));
  } catch (const std::exception&) {
    // No description: absent (or removed concurrently), unless it was found corrupted before.
    if (quarantine_.holds("meshes", digest + ".json") || quarantine_.holds("meshes", digest + ".mesh"))
      result.found = Found::kQuarantined;
    return result;
  }
  result.found = Found::kCorrupted;
  try {
    result.info = from_json(unseal_json(text));
  } catch (const std::exception& e) {
    result.problem = std::string("unreadable description: ") + e.what();
    return result;
  }
  if (result.info.digest != digest) {
    result.problem = "its description names another mesh";
    return result;
  }
  std::error_code error;
  const auto size = fs::file_size(mesh_path(digest), error);
  if (error || static_cast<int64_t>(size) != result.info.size_bytes) {
    if (error && !fs::exists(info_path(digest))) return Lookup{};  // removed concurrently
    result.problem = error ? "its bytes are missing"
                           : "its size is " + std::to_string(size) + " bytes, not " + std::to_string(result.info.size_bytes);
    return result;
  }
  if (with_bytes) {
    try {
      result.bytes = read_whole_file(mesh_path(digest));
    } catch (const std::exception&) {
      if (!fs::exists(info_path(digest))) return Lookup{};  // removed concurrently
      result.problem = "its bytes cannot be read";
      return result;
    }
    if (sha256_hex(result.bytes) != digest) {
      result.problem = "its bytes no longer hash to its name";
      return result;
    }
  }
  result.found = Found::kIntact;
  return result;
}

MeshStore::Lookup MeshStore::quarantine_if_corrupted(const std::string& digest, bool with_bytes) {
  Lookup result = lookup(digest, with_bytes);
  if (result.found != Found::kCorrupted) return result;
  // The bytes first: a crash between the two moves leaves a description without bytes,
  // which the next lookup finds corrupted too.
  if (fs::exists(mesh_path(digest))) quarantine_.set_aside("meshes", mesh_path(digest), result.problem);
  quarantine_.set_aside("meshes", info_path(digest), result.problem);
  result.found = Found::kQuarantined;
  return result;
}

MeshStore::Lookup MeshStore::checked(const std::string& digest, bool with_bytes) {
  Lookup result = lookup(digest, with_bytes);
  if (result.found != Found::kCorrupted) return result;
  std::lock_guard lock(mutex_);
  return quarantine_if_corrupted(digest, with_bytes);
}

std::optional<MeshInfo> MeshStore::describe(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/false);
  if (result.found == Found::kQuarantined) throw ServiceError(Kind::kDataLoss, corrupted_message(digest));
  if (result.found == Found::kAbsent) return std::nullopt;
  return std::move(result.info);
}

std::optional<MeshInfo> MeshStore::get(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/true);
  if (result.found == Found::kQuarantined) throw ServiceError(Kind::kDataLoss, corrupted_message(digest));
  if (result.found == Found::kAbsent) return std::nullopt;
  return std::move(result.info);
}

std::optional<MeshInfo> MeshStore::find_intact(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/true);
  if (result.found != Found::kIntact) return std::nullopt;
  return std::move(result.info);
}

std::vector<MeshInfo> MeshStore::list() {
  std::vector<std::string> digests;
  for (const auto& entry : fs::directory_iterator(dir_))
    if (entry.path().extension() == ".json") digests.push_back(entry.path().stem().string());
  std::sort(digests.begin(), digests.end());
  std::vector<MeshInfo> meshes;
  for (const auto& digest : digests) {
    Lookup result = checked(digest, /*with_bytes=*/false);
    if (result.found == Found::kIntact) meshes.push_back(std::move(result.info));
  }
  return meshes;
}

bool MeshStore::remove(const std::string& digest) {
  std::lock_guard lock(mutex_);
  if (lookup(digest, false).found == Found::kAbsent) return false;
  guard_storage_write("cannot remove", info_path(digest), [&] {
    fs::remove(info_path(digest));  // the mesh is gone once its description is
    fs::remove(mesh_path(digest));
  });
  fsync_path(dir_);
  return true;
}

MeshStore::StoredMesh MeshStore::read(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/true);
  if (result.found == Found::kQuarantined) throw ServiceError(Kind::kDataLoss, corrupted_message(digest));
  if (result.found == Found::kAbsent)
    throw ServiceError(Kind::kNotFound, "no mesh meshes/" + digest + " on this server; upload it first");
  return {std::move(result.info), std::move(result.bytes)};
}

}  // namespace isocorr::server

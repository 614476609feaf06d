#include "storage/mesh_store.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <random>

#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include "service_error.h"
#include "storage/durable_file.h"
#include "storage/sealed_json.h"
#include "storage/storage_failure.h"

namespace isocorr::server {
namespace fs = std::filesystem;
using Kind = ServiceError::Kind;

namespace {

std::string random_suffix() {
  static std::mutex mutex;
  static std::mt19937_64 generator{std::random_device{}()};
  std::lock_guard lock(mutex);
  return std::to_string(generator());
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
  for (const auto& entry : fs::directory_iterator(dir_)) {
    const fs::path& path = entry.path();
    const std::string name = path.filename().string();
    if (name.ends_with(kPendingSuffix)) {
      const std::string digest = name.substr(0, name.size() - std::string_view(kPendingSuffix).size());
      if (fs::exists(info_path(digest)) && !fs::exists(mesh_path(digest))) {
        // Described but not yet renamed (a commit stopped between the two, or a removal
        // before it dropped the description): the bytes are checked when read.
        fs::rename(path, mesh_path(digest));
        spdlog::info("storage: finishing the store of mesh {}", digest);
      } else {
        spdlog::info("storage: removing {} left by an unfinished upload or removal", path.string());
        fs::remove(path);
      }
    } else if (path.extension() == ".tmp") {
      spdlog::info("storage: removing {} left by an unfinished write", path.string());
      fs::remove(path);
    } else if (path.extension() == ".mesh" && !fs::exists(info_path(path.stem().string()))) {
      // Bytes reach their final name only after their description is on disk: this one
      // was lost. Kept for the operator and reported as lost, never deleted.
      quarantine_.set_aside("meshes", path, "its description is missing");
    }
  }
}

std::unique_ptr<MeshUpload> MeshStore::begin_upload(const std::string& digest, const std::string& filename,
                                                    int64_t declared_size) {
  check_upload_header(digest, declared_size);
  const fs::path temp = temp_dir_ / (digest + "." + random_suffix());
  return std::unique_ptr<MeshUpload>(new DirectoryMeshUpload(*this, digest, filename, temp));
}

DirectoryMeshUpload::DirectoryMeshUpload(MeshStore& store, std::string digest, std::string filename, fs::path temp)
    : MeshUpload(std::move(digest), std::move(filename), store.max_mesh_bytes_), store_(store), temp_(std::move(temp)),
      file_(std::fopen(temp_.c_str(), "wb"), &std::fclose) {
  if (!file_) throw_write_failure("cannot create", temp_, errno);
}

DirectoryMeshUpload::~DirectoryMeshUpload() {
  file_.reset();
  std::error_code ignored;
  fs::remove(temp_, ignored);
}

void DirectoryMeshUpload::keep(std::string_view bytes) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_.get()) != bytes.size())
    throw_write_failure("cannot write", temp_, errno);
}

std::string DirectoryMeshUpload::kept_bytes() {
  if (std::fflush(file_.get()) != 0) throw_write_failure("cannot write", temp_, errno);
  if (std::fclose(file_.release()) != 0) throw_write_failure("cannot write", temp_, errno);
  return read_whole_file(temp_);
}

MeshInfo DirectoryMeshUpload::store(const MeshInfo& info) {
  std::lock_guard lock(store_.mutex_);
  // A concurrent upload won; a corrupted copy is quarantined (and replaced below).
  MeshStore::Lookup existing = store_.quarantine_if_corrupted(digest_, /*with_bytes=*/true);
  if (existing.found == MeshStore::Found::kIntact) return existing.info;
  // The bytes wait under a pending name until their description is on disk, so that a
  // .mesh without its .json is never an unfinished upload but lost metadata.
  const fs::path pending = store_.pending_path(digest_), mesh_path = store_.mesh_path(digest_);
  try {
    fsync_path(temp_);
    guard_storage_write("cannot store", pending, [&] { fs::rename(temp_, pending); });
    write_file_durably(store_.info_path(digest_), seal_json(mesh_info_to_json(info)));
    guard_storage_write("cannot store", mesh_path, [&] { fs::rename(pending, mesh_path); });
    fsync_path(store_.dir_);
  } catch (...) {
    std::error_code ignored;  // not acknowledged: nothing may stay behind
    for (const fs::path& path : {store_.info_path(digest_), mesh_path, pending}) fs::remove(path, ignored);
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
    result.info = mesh_info_from_json(unseal_json(text));
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
  if (result.found == Found::kQuarantined) throw ServiceError(Kind::kDataLoss, corrupted_mesh_message(digest));
  if (result.found == Found::kAbsent) return std::nullopt;
  return std::move(result.info);
}

std::optional<MeshInfo> MeshStore::get(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/true);
  if (result.found == Found::kQuarantined) throw ServiceError(Kind::kDataLoss, corrupted_mesh_message(digest));
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
  // Bytes first to their pending name: whatever a crash interrupts, the next start either
  // keeps the whole mesh or removes it, and never finds bytes without a description.
  guard_storage_write("cannot remove", info_path(digest), [&] {
    if (fs::exists(mesh_path(digest))) fs::rename(mesh_path(digest), pending_path(digest));
    fs::remove(info_path(digest));  // the mesh is gone once its description is
    fs::remove(pending_path(digest));
  });
  fsync_path(dir_);
  return true;
}

MeshStore::StoredMesh MeshStore::read(const std::string& digest) {
  Lookup result = checked(digest, /*with_bytes=*/true);
  if (result.found == Found::kQuarantined) throw ServiceError(Kind::kDataLoss, corrupted_mesh_message(digest));
  if (result.found == Found::kAbsent)
    throw ServiceError(Kind::kNotFound, "no mesh meshes/" + digest + " on this server; upload it first");
  return {std::move(result.info), std::move(result.bytes)};
}

}  // namespace isocorr::server

#include "remote/mesh_upload.h"

#include <filesystem>

#include "isocorr/util/sha256.h"
#include "mesh_files.h"
#include "remote/rpc_error.h"

namespace isocorr::cli {
namespace {

constexpr size_t kChunkBytes = 1 << 20;  // well under gRPC's 4 MiB message limit

}  // namespace

UploadOutcome ensure_uploaded(Connection& connection, const std::string& path, const std::string& role) {
  const std::string bytes = read_mesh_file(role, path);
  Sha256 hasher;
  hasher.update(bytes);
  const std::string digest = hasher.hex_digest();

  UploadOutcome outcome;
  v1::GetMeshRequest get;
  get.set_name("meshes/" + digest);
  auto lookup = connection.context();
  const grpc::Status found = connection.meshes().GetMesh(lookup.get(), get, &outcome.mesh);
  if (found.ok()) return outcome;
  // DATA_LOSS: the server holds a corrupted copy, which uploading the right bytes repairs.
  if (found.error_code() != grpc::StatusCode::NOT_FOUND && found.error_code() != grpc::StatusCode::DATA_LOSS)
    check_rpc(found, *lookup, "cannot look up " + mesh_file_label(role, path));

  auto context = connection.context(/*long_call=*/true);
  v1::UploadMeshResponse response;
  auto writer = connection.meshes().UploadMesh(context.get(), &response);
  v1::UploadMeshRequest request;
  request.mutable_header()->set_sha256(digest);
  request.mutable_header()->set_filename(std::filesystem::path(path).filename().string());
  request.mutable_header()->set_size_bytes(static_cast<int64_t>(bytes.size()));
  // A failed write means the server has ended the call (an error, or it found the digest
  // meanwhile); Finish tells which.
  bool open = writer->Write(request);
  for (size_t offset = 0; open && offset < bytes.size(); offset += kChunkBytes) {
    request.set_chunk(bytes.substr(offset, kChunkBytes));
    open = writer->Write(request);
  }
  if (open) writer->WritesDone();
  check_rpc(writer->Finish(), *context, "cannot upload " + mesh_file_label(role, path));
  outcome.mesh = response.mesh();
  outcome.uploaded = !response.already_existed();
  return outcome;
}

}  // namespace isocorr::cli

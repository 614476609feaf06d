#include "api/mesh_service.h"

#include <spdlog/spdlog.h>

#include "api/call_guard.h"
#include "api/error_details.h"
#include "api/paging.h"
#include "api/request_limits.h"
#include "api/resource_codec.h"
#include "isocorr/util/sha256.h"
#include "metrics/server_metrics.h"
#include "service_error.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;

MeshInfo MeshServiceImpl::require(const std::string& name) const {
  require_bounded("name", name, kMaxNameBytes);
  const std::string digest = mesh_digest_from_name(name);
  if (digest.empty())
    throw field_error("name", "INVALID_NAME",
                      "mesh names look like meshes/{sha256} (64 lower-case hex digits), got " + quoted_prefix(name));
  auto info = meshes_.get(digest);
  if (!info)
    throw DetailedError(Kind::kNotFound, "MESH_NOT_FOUND", "name",
                        "no mesh " + name + " on this server; upload it first");
  return *info;
}

grpc::Status MeshServiceImpl::UploadMesh(grpc::ServerContext* context,
                                         grpc::ServerReader<v1::UploadMeshRequest>* reader,
                                         v1::UploadMeshResponse* response) {
  return guarded_call("UploadMesh", *context, auth_, [&](const CallInfo& call) {
    v1::UploadMeshRequest request;
    if (!reader->Read(&request) || !request.has_header())
      throw field_error("header", "INVALID_UPLOAD", "the first UploadMesh message must carry the header");
    const v1::UploadMeshRequest::Header header = request.header();  // a copy: `request` is reused below
    if (!is_sha256_hex(header.sha256()))
      throw field_error("header.sha256", "INVALID_UPLOAD",
                        "sha256 must be 64 lower-case hex characters, got " + quoted_prefix(header.sha256()));
    require_bounded("header.filename", header.filename(), kMaxFilenameBytes);
    require_upload_size(header.size_bytes());
    if (auto existing = meshes_.find_intact(header.sha256())) {  // a corrupted copy is replaced
      // Content-addressed: same digest, same bytes. The rest of the stream is not read.
      *response->mutable_mesh() = mesh_to_proto(*existing, cache_.state_of_mesh(existing->digest));
      response->set_already_existed(true);
      return grpc::Status::OK;
    }
    auto upload = meshes_.begin_upload(header.sha256(), header.filename(), header.size_bytes());
    const UploadBudget::Reservation reservation = upload_budget_.reserve(header.size_bytes());
    reader->SendInitialMetadata();  // tells a waiting client that the upload was admitted
    int64_t received = 0;
    while (reader->Read(&request)) {
      if (request.has_header())
        throw field_error("header", "INVALID_UPLOAD", "only the first message may carry a header");
      received += static_cast<int64_t>(request.chunk().size());
      server_metrics().upload_bytes.add(static_cast<double>(request.chunk().size()));
      if (received > header.size_bytes())
        throw field_error("header.size_bytes", "INVALID_UPLOAD",
                          "more bytes than the header's size_bytes " + std::to_string(header.size_bytes()) +
                              " were sent");
      upload->append(request.chunk());
    }
    if (context->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "upload cancelled by the client");
    if (received != header.size_bytes())
      throw field_error("header.size_bytes", "INVALID_UPLOAD",
                        "the upload ended after " + std::to_string(received) + " of the header's size_bytes " +
                            std::to_string(header.size_bytes()) + " bytes");
    const MeshInfo info = upload->commit();
    spdlog::info("[{}] stored mesh {} ({}, {} vertices, {} bytes)", call.request_id, info.digest,
                 escape_text(info.filename),
                 info.vertex_count, info.size_bytes);
    *response->mutable_mesh() = mesh_to_proto(info, cache_.state_of_mesh(info.digest));
    return grpc::Status::OK;
  });
}

grpc::Status MeshServiceImpl::GetMesh(grpc::ServerContext* context, const v1::GetMeshRequest* request,
                                      v1::Mesh* response) {
  return guarded_call("GetMesh", *context, auth_, [&](const CallInfo&) {
    const MeshInfo info = require(request->name());
    *response = mesh_to_proto(info, cache_.state_of_mesh(info.digest));
    return grpc::Status::OK;
  });
}

grpc::Status MeshServiceImpl::ListMeshes(grpc::ServerContext* context, const v1::ListMeshesRequest* request,
                                         v1::ListMeshesResponse* response) {
  return guarded_call("ListMeshes", *context, auth_, [&](const CallInfo&) {
    const std::vector<MeshInfo> meshes = meshes_.list();
    response->set_next_page_token(
        fill_page(*response->mutable_meshes(), meshes.size(), request->page_size(), request->page_token(),
                  [&](size_t i) { return mesh_to_proto(meshes[i], cache_.state_of_mesh(meshes[i].digest)); }));
    return grpc::Status::OK;
  });
}

grpc::Status MeshServiceImpl::DeleteMesh(grpc::ServerContext* context, const v1::DeleteMeshRequest* request,
                                         v1::DeleteMeshResponse*) {
  return guarded_call("DeleteMesh", *context, auth_, [&](const CallInfo&) {
    const MeshInfo info = require(request->name());
    if (jobs_.mesh_in_use(info.digest))
      throw DetailedError(Kind::kFailedPrecondition, "MESH_IN_USE", "name",
                          request->name() + " is used by a queued or running job; cancel the job or wait for it");
    meshes_.remove(info.digest);
    return grpc::Status::OK;
  });
}

}  // namespace isocorr::server

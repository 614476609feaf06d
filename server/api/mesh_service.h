// isocorr.v1.MeshService: translates requests to the mesh store and back.
#pragma once

#include "api/auth.h"
#include "api/upload_budget.h"
#include "isocorr/v1/isocorr.grpc.pb.h"
#include "jobs/job_coordinator.h"
#include "jobs/shape_cache.h"
#include "storage/mesh_repository.h"

namespace isocorr::server {

class MeshServiceImpl final : public v1::MeshService::Service {
 public:
  MeshServiceImpl(MeshRepository& meshes, ShapeCache& cache, JobCoordinator& jobs, UploadBudget& upload_budget,
                  const TokenAuth& auth)
      : meshes_(meshes), cache_(cache), jobs_(jobs), upload_budget_(upload_budget), auth_(auth) {}

  grpc::Status UploadMesh(grpc::ServerContext* context, grpc::ServerReader<v1::UploadMeshRequest>* reader,
                          v1::UploadMeshResponse* response) override;
  grpc::Status GetMesh(grpc::ServerContext* context, const v1::GetMeshRequest* request, v1::Mesh* response) override;
  grpc::Status ListMeshes(grpc::ServerContext* context, const v1::ListMeshesRequest* request,
                          v1::ListMeshesResponse* response) override;
  grpc::Status DeleteMesh(grpc::ServerContext* context, const v1::DeleteMeshRequest* request,
                          v1::DeleteMeshResponse* response) override;

 private:
  MeshInfo require(const std::string& name) const;

  MeshRepository& meshes_;
  ShapeCache& cache_;
  JobCoordinator& jobs_;
  UploadBudget& upload_budget_;
  const TokenAuth& auth_;
};

}  // namespace isocorr::server

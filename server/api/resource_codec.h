// Domain records -> API resources (isocorr.v1.Mesh, isocorr.v1.Job) and resource names.
#pragma once

#include <string>

#include "isocorr/v1/isocorr.pb.h"
#include "storage/job_record.h"
#include "jobs/shape_cache.h"
#include "storage/mesh_store.h"

namespace isocorr::server {

v1::Mesh mesh_to_proto(const MeshInfo& info, ShapeCache::MeshState state);
v1::Job job_to_proto(const JobRecord& job);

// "meshes/{sha256}" -> sha256 (64 lower-case hex) and "jobs/{id}" -> id; empty when
// `name` has another form.
std::string mesh_digest_from_name(const std::string& name);
std::string job_id_from_name(const std::string& name);

}  // namespace isocorr::server

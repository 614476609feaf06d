// Where meshes, jobs and results live, chosen by --store: the data directory (the
// default, one server) or a PostgreSQL database shared by several replicas.
#pragma once

#include <memory>

#include "jobs/job_coordinator.h"
#include "jobs/shape_cache.h"
#include "server_options.h"
#include "storage/mesh_repository.h"

namespace isocorr::server {

class PgDatabase;
class PgJobStore;
class JobJournal;
class DataDirectoryLock;

struct Store {
  ~Store();
  std::unique_ptr<DataDirectoryLock> data_dir_lock;  // declared first: released last
  std::unique_ptr<PgDatabase> database;
  std::unique_ptr<MeshRepository> meshes;
  std::unique_ptr<JobJournal> journal;
  std::unique_ptr<PgJobStore> job_store;
  std::unique_ptr<JobCoordinator> jobs;  // declared last: its workers stop first
};

// Throws std::runtime_error when the store cannot be opened, or when another server holds
// the data directory (naming its pid).
std::unique_ptr<Store> open_store(const ServerOptions& options, ShapeCache& cache);

}  // namespace isocorr::server

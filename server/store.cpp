#include "store.h"

#include <unistd.h>

#include <filesystem>

#include "jobs/job_manager.h"
#include "jobs/shared_job_manager.h"
#include "postgres/pg_database.h"
#include "postgres/pg_job_store.h"
#include "postgres/pg_mesh_store.h"
#include "storage/data_directory.h"
#include "storage/job_journal.h"
#include "storage/job_record.h"
#include "storage/mesh_store.h"

namespace isocorr::server {
namespace {

// Unique per process even where host names and pids repeat (containers restarted in one
// pod are all pid 1): a replica must never renew or end another live replica's jobs.
std::string default_replica_id() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  return std::string(host) + "-" + std::to_string(getpid()) + "-" + new_job_id().substr(0, 6);
}

}  // namespace

Store::~Store() = default;

std::unique_ptr<Store> open_store(const ServerOptions& options, ShapeCache& cache) {
  auto store = std::make_unique<Store>();
  if (options.store.empty()) {
    std::filesystem::create_directories(options.data_dir);
    store->data_dir_lock = std::make_unique<DataDirectoryLock>(options.data_dir);  // before anything is read
    auto meshes = std::make_unique<MeshStore>(options.data_dir, options.max_mesh_bytes);
    store->journal = std::make_unique<JobJournal>(options.data_dir);
    store->jobs = std::make_unique<JobManager>(
        JobManagerOptions{options.threads, options.max_queued_jobs, options.max_attempts,
                          std::chrono::seconds(options.job_time_limit_seconds)},
        *meshes, *store->journal, cache);
    store->meshes = std::move(meshes);
    return store;
  }
  store->database = std::make_unique<PgDatabase>(options.store);
  store->meshes = std::make_unique<PgMeshStore>(*store->database, options.max_mesh_bytes);
  store->job_store = std::make_unique<PgJobStore>(*store->database);
  SharedJobOptions shared{options.threads, options.max_queued_jobs, options.max_attempts,
                          std::chrono::milliseconds(static_cast<int64_t>(options.lease_seconds * 1000)),
                          options.replica_id.empty() ? default_replica_id() : options.replica_id,
                          std::chrono::seconds(options.job_time_limit_seconds)};
  store->jobs = std::make_unique<SharedJobManager>(shared, *store->job_store, *store->meshes, cache);
  return store;
}

}  // namespace isocorr::server

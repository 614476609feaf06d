// Every setting of isocorr-server, with its default and flag.
#pragma once

#include <cstdint>
#include <string>

namespace CLI {
class App;
}

namespace isocorr::server {

struct ServerOptions {
  std::string listen = "127.0.0.1:50051";  // loopback unless asked otherwise
  std::string data_dir = "isocorr-data";
  // Empty: meshes, jobs and results live under data_dir. postgresql://...: in that shared
  // database, so that several replicas serve the same store.
  std::string store;
  double lease_seconds = 30;                // a running job's lease in the shared store
  std::string replica_id;                   // claimed_by of this replica's jobs (default host-pid-random)
  int threads = 1;                          // jobs run at once; each uses all cores (engine default)
  int64_t cache_bytes = int64_t{2} << 30;   // preprocessed meshes kept in memory
  int64_t max_mesh_bytes = int64_t{128} << 20;
  // Memory all uploads in progress may take together, each UploadBudget::memory_for its size.
  int64_t upload_memory = int64_t{4} << 30;
  int max_queued_jobs = 64;
  int max_attempts = 2;                     // starts of a job interrupted by crashes before it fails
  int job_time_limit_seconds = 3600;        // a job running longer fails with DEADLINE_EXCEEDED; 0 = none
  int shutdown_grace_seconds = 5;
  std::string token_file, tls_cert, tls_key;
  std::string port_file;                    // written with the bound port (for --listen HOST:0)
  std::string log_level = "info";
  std::string metrics_listen;               // Prometheus endpoint; empty = off
  std::string metrics_port_file;            // written with its bound port (for PORT 0)
};

void add_server_flags(CLI::App& app, ServerOptions& options);

}  // namespace isocorr::server

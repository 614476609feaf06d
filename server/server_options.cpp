#include "server_options.h"

#include <CLI/CLI.hpp>

namespace isocorr::server {

void add_server_flags(CLI::App& app, ServerOptions& o) {
  app.add_option("--listen", o.listen, "HOST:PORT to listen on (port 0 picks a free one)")->capture_default_str();
  app.add_option("--data-dir", o.data_dir, "directory of the durable store (meshes, jobs, results)")->capture_default_str();
  app.add_option("--store", o.store,
                 "postgresql://USER@HOST/DB (a libpq connection URI): keep meshes, jobs and results in this "
                 "PostgreSQL database, shared by every replica given the same URI; --data-dir is then unused")
      ->check([](const std::string& uri) {
        return uri.rfind("postgresql://", 0) == 0 || uri.rfind("postgres://", 0) == 0
                   ? std::string()
                   : std::string("--store takes a postgresql:// URI");
      });
  app.add_option("--lease-seconds", o.lease_seconds,
                 "with --store: a running job's lease, renewed by its replica; another replica takes the job "
                 "over this long after its replica died")
      ->check(CLI::Range(0.2, 3600.0))->capture_default_str();
  app.add_option("--replica-id", o.replica_id, "with --store: this replica's name in the job queue, unique per running server (default "
                 "HOST-PID-RANDOM)");
  app.add_option("--threads", o.threads, "jobs run at once (worker threads)")->check(CLI::Range(1, 256))->capture_default_str();
  app.add_option("--cache-bytes", o.cache_bytes, "memory for preprocessed meshes shared by jobs (LRU)")->capture_default_str();
  app.add_option("--max-mesh-bytes", o.max_mesh_bytes, "largest mesh file accepted by UploadMesh")->capture_default_str();
  app.add_option("--upload-memory", o.upload_memory,
                 "memory the uploads in progress may take together, each 18 times its size (the reading "
                 "peak and its bytes); beyond it UploadMesh fails with RESOURCE_EXHAUSTED (at least 18 times "
                 "--max-mesh-bytes)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--max-queued-jobs", o.max_queued_jobs, "CreateMatchJob fails with RESOURCE_EXHAUSTED beyond this")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--max-attempts", o.max_attempts, "times a job interrupted by a crash is started before it fails")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--job-time-limit", o.job_time_limit_seconds,
                 "seconds a job may run before it fails with DEADLINE_EXCEEDED (0: no limit)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--shutdown-grace", o.shutdown_grace_seconds, "seconds open calls get on SIGTERM")->capture_default_str();
  app.add_option("--token-file", o.token_file, "require 'authorization: Bearer <token>' with the token in this file")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-cert", o.tls_cert, "PEM certificate chain (enables TLS)")->check(CLI::ExistingFile);
  app.add_option("--tls-key", o.tls_key, "PEM private key for --tls-cert")->check(CLI::ExistingFile);
  app.add_option("--port-file", o.port_file, "write the bound port to this file once listening");
  app.add_option("--metrics-listen", o.metrics_listen,
                 "serve Prometheus metrics at http://HOST:PORT/metrics (PORT alone: on 127.0.0.1; off unless given)");
  app.add_option("--metrics-port-file", o.metrics_port_file, "write the metrics endpoint's bound port to this file")
      ->needs("--metrics-listen");
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn or error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}))->capture_default_str();
}

}  // namespace isocorr::server

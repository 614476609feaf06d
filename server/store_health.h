// grpc.health.v1 follows the store, which readiness probes rely on: the server ("") and its
// services are NOT_SERVING while it cannot be reached, SERVING again once it can. A thread
// probes it every second: the data directory must exist and be writable; PostgreSQL must
// answer SELECT 1 (on a connection of the probe's own, so that a busy pool does not make the
// server look down). The service name "liveness" stays SERVING while the process answers:
// a liveness probe must not restart every replica because the shared store is down.
#pragma once

#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <grpcpp/health_check_service_interface.h>
#include <pqxx/connection>

#include "server_options.h"

namespace isocorr::server {

inline constexpr const char* kLivenessService = "liveness";

class StoreHealth {
 public:
  // Starts probing; `health` must outlive this object.
  StoreHealth(const ServerOptions& options, grpc::HealthCheckServiceInterface& health);
  ~StoreHealth();  // stops the probe
  StoreHealth(const StoreHealth&) = delete;
  StoreHealth& operator=(const StoreHealth&) = delete;

 private:
  void run();
  void set_serving(bool serving);
  // Empty when the store can be reached, else why not.
  std::string probe();
  std::string probe_postgres();

  const std::string data_dir_, postgres_url_;  // one of them is used: --store or --data-dir
  grpc::HealthCheckServiceInterface& health_;
  std::unique_ptr<pqxx::connection> connection_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace isocorr::server

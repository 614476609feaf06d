// A channel to isocorr-server with the user's connection flags (address, TLS, token),
// and the stubs of every service the client calls.
#pragma once

#include <chrono>
#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "grpc/health/v1/health.grpc.pb.h"
#include "isocorr/v1/isocorr.grpc.pb.h"

namespace CLI {
class App;
}

namespace isocorr::cli {

struct ConnectionOptions {
  std::string server;      // HOST:PORT; empty = not given
  std::string token_file;  // bearer token sent with every call
  bool tls = false;        // TLS with the system's root certificates
  std::string tls_ca;      // TLS with this root certificate (PEM)
  int timeout_seconds = 30;  // deadline of short calls (not watch/wait/transfers)

  static constexpr const char* kDefaultServer = "127.0.0.1:50051";
};

// Registers --server, --token-file, --tls, --tls-ca and --timeout on the top-level app,
// where subcommands find them through CLI11's fallthrough (before or after the subcommand).
void add_connection_flags(CLI::App& app, ConnectionOptions& options);

class Connection {
 public:
  explicit Connection(const ConnectionOptions& options);

  v1::MeshService::Stub& meshes() { return *meshes_; }
  v1::JobService::Stub& jobs() { return *jobs_; }
  grpc::health::v1::Health::Stub& health() { return *health_; }

  // A context carrying the token, with the short-call deadline (or none when `long_call`).
  std::unique_ptr<grpc::ClientContext> context(bool long_call = false) const;
  const std::string& address() const { return address_; }

 private:
  std::string address_, token_;
  int timeout_seconds_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::MeshService::Stub> meshes_;
  std::unique_ptr<v1::JobService::Stub> jobs_;
  std::unique_ptr<grpc::health::v1::Health::Stub> health_;
};

}  // namespace isocorr::cli

// `isocorr-server`: the gRPC service (isocorr.v1) over the engine, with a durable store
// under --data-dir (or shared with other replicas in PostgreSQL, --store), a cache of
// preprocessed meshes and a pool of job workers.
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>

#include <CLI/CLI.hpp>
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include "api/auth.h"
#include "api/job_service.h"
#include "api/mesh_service.h"
#include "api/upload_budget.h"
#include "jobs/shape_cache.h"
#include "metrics/live_metrics.h"
#include "metrics/metrics_endpoint.h"
#include "server_options.h"
#include "store.h"
#include "store_health.h"
#include "storage/durable_file.h"
#include "isocorr/util/huge_page_malloc.h"

namespace isocorr::server {
namespace {

std::string read_secret(const std::string& path, const char* what) {
  std::string text = read_whole_file(path);
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
  if (text.empty()) throw std::runtime_error(std::string(what) + " '" + path + "' is empty");
  return text;
}

std::shared_ptr<grpc::ServerCredentials> credentials(const ServerOptions& options) {
  if (options.tls_cert.empty() != options.tls_key.empty())
    throw std::runtime_error("--tls-cert and --tls-key go together");
  if (options.tls_cert.empty()) return grpc::InsecureServerCredentials();
  grpc::SslServerCredentialsOptions ssl;
  ssl.pem_key_cert_pairs.push_back({read_whole_file(options.tls_key), read_whole_file(options.tls_cert)});
  return grpc::SslServerCredentials(ssl);
}

// Linking gRPC's reflection library registers its plugin for every server at load time, so
// leaving it out takes removing it: this option does so on a server that requires a token.
class WithoutReflection final : public grpc::ServerBuilderOption {
 public:
  void UpdateArguments(grpc::ChannelArguments*) override {}
  void UpdatePlugins(std::vector<std::unique_ptr<grpc::ServerBuilderPlugin>>* plugins) override {
    std::erase_if(*plugins, [](const auto& plugin) { return plugin->name() == "proto_server_reflection"; });
  }
};

// Shutdown waits for open calls and running jobs, and a stuck one (a computation that never
// looks at its cancel flag) would keep the process alive past any orchestrator's grace
// period. Nothing is lost by ending it: every acknowledged byte is already durable, as
// after a kill -9, and interrupted jobs are taken up at the next start. So a second signal,
// or the grace period and a second more passing, ends the process at once.
void end_process_if_shutdown_stalls(const sigset_t& signals, int grace_seconds) {
  std::thread([signals, grace_seconds] {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(grace_seconds + 1);
    int second = -1;
    for (;;) {  // a wait interrupted by another signal (EINTR) goes on until the deadline
      const auto left = std::chrono::duration_cast<std::chrono::nanoseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) break;
      const timespec timeout{static_cast<time_t>(left.count() / 1'000'000'000), static_cast<long>(left.count() % 1'000'000'000)};
      second = sigtimedwait(&signals, nullptr, &timeout);
      if (second > 0 || errno != EINTR) break;
    }
    // No logger from here: main may have returned already and be tearing it down.
    char message[128];
    const int length =
        second > 0 ? std::snprintf(message, sizeof message, "isocorr-server: signal %d again: stopping now\n", second)
                   : std::snprintf(message, sizeof message,
                                   "isocorr-server: shutdown still not done %d s after the signal: stopping now\n",
                                   grace_seconds + 1);
    if (length > 0) (void)!write(STDERR_FILENO, message, static_cast<size_t>(length));
    std::_Exit(1);
  }).detach();
}

int run(const ServerOptions& options) {
  // SIGTERM and SIGINT are taken by sigwait below, so block them before any thread starts.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  // A file-size limit (ulimit -f) makes writes fail with EFBIG, reported like a full disk,
  // instead of killing the server.
  signal(SIGXFSZ, SIG_IGN);

  if (options.upload_memory < UploadBudget::memory_for(options.max_mesh_bytes))
    throw std::runtime_error("--upload-memory must be at least " + std::to_string(UploadBudget::kMemoryPerFileByte) +
                             " times --max-mesh-bytes, or no mesh of the largest size could be uploaded");
  const TokenAuth auth(options.token_file.empty() ? "" : read_secret(options.token_file, "token file"));
  ShapeCache cache(options.cache_bytes);
  const std::unique_ptr<Store> store = open_store(options, cache);
  MeshRepository& meshes = *store->meshes;
  JobCoordinator& jobs = *store->jobs;
  jobs.recover_and_start();
  std::unique_ptr<MetricsEndpoint> metrics;
  if (!options.metrics_listen.empty()) {
    metrics = std::make_unique<MetricsEndpoint>(options.metrics_listen, [&] { return metrics_text(jobs, cache); });
    if (!options.metrics_port_file.empty())
      write_file_durably(options.metrics_port_file, std::to_string(metrics->port()) + "\n");
  }

  UploadBudget upload_budget(options.upload_memory);
  MeshServiceImpl mesh_service(meshes, cache, jobs, upload_budget, auth);
  JobServiceImpl job_service(jobs, auth);
  grpc::EnableDefaultHealthCheckService(true);
  // Reflection cannot check our bearer token, so it is offered only when there is none.
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();  // (loading the library does so too)
  grpc::ServerBuilder builder;
  if (auth.enabled()) builder.SetOption(std::make_unique<WithoutReflection>());
  // With SO_REUSEPORT, gRPC 1.51 opens one more listener per extra poller, and for port 0
  // each of those binds a port of its own that nobody is told about. Without it there is
  // one listener, and a second server cannot silently share a fixed port either.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  int port = 0;
  builder.AddListeningPort(options.listen, credentials(options), &port);
  builder.RegisterService(&mesh_service);
  builder.RegisterService(&job_service);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) {
    spdlog::error("cannot listen on {}", options.listen);
    return 1;
  }
  // Readiness follows the store: NOT_SERVING while it cannot be reached.
  const StoreHealth store_health(options, *server->GetHealthCheckService());
  const std::string host = options.listen.substr(0, options.listen.rfind(':'));
  spdlog::info("isocorr-server listening on {}:{} ({}, {}), data in {}, {} worker(s)", host, port,
               options.tls_cert.empty() ? "plaintext" : "TLS", auth.enabled() ? "bearer token" : "no auth",
               options.store.empty() ? options.data_dir : "the shared PostgreSQL store", options.threads);
  spdlog::info("GLIBC_TUNABLES={}", malloc_tunables());
  // Absolute, so that a bare file name has a directory to sync.
  if (!options.port_file.empty())
    write_file_durably(options.port_file, std::to_string(port) + "\n");

  int signal_number = 0;
  sigwait(&signals, &signal_number);
  spdlog::info("signal {}: shutting down (running jobs are kept for the next start)", signal_number);
  end_process_if_shutdown_stalls(signals, options.shutdown_grace_seconds);
  // Watches and waits end at once with UNAVAILABLE, not CANCELLED: their jobs are kept.
  job_service.stop_long_calls();
  // Stop accepting; calls still open after the grace period are cancelled.
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(options.shutdown_grace_seconds));
  jobs.shutdown();
  metrics.reset();
  spdlog::info("stopped");
  return 0;
}

}  // namespace
}  // namespace isocorr::server

int main(int argc, char** argv) {
  isocorr::restart_with_huge_page_malloc(argv);
  isocorr::server::ServerOptions options;
  CLI::App app{"isocorr-server: the isocorr.v1 gRPC service (meshes, matching jobs, results)"};
  isocorr::server::add_server_flags(app, options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  spdlog::set_level(spdlog::level::from_str(options.log_level));
  try {
    return isocorr::server::run(options);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}

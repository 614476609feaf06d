// `isocorr health [--service NAME]`: asks the server's grpc.health.v1 service.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "remote/job_output.h"
#include "remote/remote_subcommand.h"
#include "remote/rpc_error.h"

namespace isocorr::cli {

void register_health_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto service = std::make_shared<std::string>();
  add_remote_command(app, "health", "ask the server's grpc.health.v1 service; exit 0 when it is serving", options,
                     exit_code, [service](Connection& connection, bool json) {
                       grpc::health::v1::HealthCheckRequest request;
                       request.set_service(*service);
                       grpc::health::v1::HealthCheckResponse response;
                       auto context = connection.context();
                       check_rpc(connection.health().Check(context.get(), request, &response), *context,
                                 "health check of " + connection.address());
                       const bool serving = response.status() == grpc::health::v1::HealthCheckResponse::SERVING;
                       print_line(json ? to_json(response)
                                       : grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response.status()));
                       return serving ? kExitOk : kExitUnavailable;
                     })
      ->add_option("--service", *service,
                   "the service to ask about (default: the server; \"liveness\": the process answers, whether "
                   "the store can be reached or not)");
}

}  // namespace isocorr::cli

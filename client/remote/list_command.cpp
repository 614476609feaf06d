// `isocorr list [jobs|meshes]`: every job or mesh on the server, page after page.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "remote/job_output.h"
#include "remote/remote_subcommand.h"
#include "remote/rpc_error.h"

namespace isocorr::cli {

void register_list_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto what = std::make_shared<std::string>("jobs");
  add_remote_command(app, "list", "list the server's jobs (default) or meshes", options, exit_code,
                     [what](Connection& connection, bool json) {
                       std::string token;
                       do {
                         if (*what == "meshes") {
                           v1::ListMeshesRequest request;
                           request.set_page_token(token);
                           v1::ListMeshesResponse response;
                           auto context = connection.context();
                           check_rpc(connection.meshes().ListMeshes(context.get(), request, &response), *context,
                                     "cannot list meshes");
                           for (const auto& mesh : response.meshes())
                             print_line(json ? to_json(mesh) : describe_mesh(mesh));
                           token = response.next_page_token();
                         } else {
                           v1::ListJobsRequest request;
                           request.set_page_token(token);
                           v1::ListJobsResponse response;
                           auto context = connection.context();
                           check_rpc(connection.jobs().ListJobs(context.get(), request, &response), *context,
                                     "cannot list jobs");
                           for (const auto& job : response.jobs()) print_line(json ? to_json(job) : describe_job(job));
                           token = response.next_page_token();
                         }
                       } while (!token.empty());
                       return kExitOk;
                     })
      ->add_option("what", *what, "jobs or meshes (one JSON object per line with --json)")
      ->check(CLI::IsMember({"jobs", "meshes"}));
}

}  // namespace isocorr::cli

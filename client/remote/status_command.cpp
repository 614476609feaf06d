// `isocorr status NAME`: one job (jobs/ID or ID) or one mesh (meshes/SHA256).
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "remote/job_follow.h"
#include "remote/job_output.h"
#include "remote/remote_subcommand.h"
#include "remote/rpc_error.h"

namespace isocorr::cli {

void register_status_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto name = std::make_shared<std::string>();
  add_remote_command(app, "status", "show a job (jobs/ID or ID) or a mesh (meshes/SHA256)", options, exit_code,
                     [name](Connection& connection, bool json) {
                       if (name->rfind("meshes/", 0) == 0) {
                         v1::GetMeshRequest request;
                         request.set_name(*name);
                         v1::Mesh mesh;
                         auto context = connection.context();
                         check_rpc(connection.meshes().GetMesh(context.get(), request, &mesh), *context,
                                   "cannot get " + *name);
                         print_line(json ? to_json(mesh) : describe_mesh(mesh));
                         return kExitOk;
                       }
                       v1::GetJobRequest request;
                       request.set_name(job_name(*name));
                       v1::Job job;
                       auto context = connection.context();
                       check_rpc(connection.jobs().GetJob(context.get(), request, &job), *context,
                                 "cannot get " + request.name());
                       print_line(json ? to_json(job) : describe_job(job));
                       return kExitOk;
                     })
      ->add_option("name", *name, "jobs/ID, ID or meshes/SHA256")->required();
}

}  // namespace isocorr::cli

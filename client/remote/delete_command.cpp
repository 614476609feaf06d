// `isocorr delete MESH`: deletes a mesh (meshes/SHA256) from the server.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "remote/remote_subcommand.h"
#include "remote/rpc_error.h"

namespace isocorr::cli {

void register_delete_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto name = std::make_shared<std::string>();
  add_remote_command(app, "delete", "delete a mesh from the server", options, exit_code,
                     [name](Connection& connection, bool json) {
                       v1::DeleteMeshRequest request;
                       request.set_name(*name);
                       v1::DeleteMeshResponse response;
                       auto context = connection.context();
                       check_rpc(connection.meshes().DeleteMesh(context.get(), request, &response), *context,
                                 "cannot delete " + *name);
                       print_line(json ? "{}" : "deleted " + *name);
                       return kExitOk;
                     })
      ->add_option("mesh", *name, "meshes/SHA256")->required();
}

}  // namespace isocorr::cli

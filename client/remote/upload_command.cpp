// `isocorr upload FILE...`: puts mesh files on the server and prints their names.
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "remote/job_output.h"
#include "remote/mesh_upload.h"
#include "remote/remote_subcommand.h"

namespace isocorr::cli {

void register_upload_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto files = std::make_shared<std::vector<std::string>>();
  add_remote_command(app, "upload", "upload mesh files (skipped when the server has them); prints their names",
                     options, exit_code, [files](Connection& connection, bool json) {
                       for (const auto& file : *files) {
                         const UploadOutcome outcome = ensure_uploaded(connection, file);
                         if (json)
                           print_line("{\"mesh\":" + to_json(outcome.mesh) + ",\"uploaded\":" +
                                      (outcome.uploaded ? "true" : "false") + "}");
                         else
                           print_line(describe_mesh(outcome.mesh) +
                                      (outcome.uploaded ? "" : "  (already on the server)"));
                       }
                       return kExitOk;
                     })
      ->add_option("files", *files, "mesh files (OFF, OBJ, PLY)")->required()->check(CLI::ExistingFile);
}

}  // namespace isocorr::cli

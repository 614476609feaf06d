// `isocorr submit SOURCE TARGET [settings]`: creates a match job and prints its name at once.
#include <filesystem>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "codec/settings_codec.h"
#include "commands.h"
#include "mesh_files.h"
#include "remote/job_output.h"
#include "remote/mesh_upload.h"
#include "remote/remote_subcommand.h"
#include "remote/rpc_error.h"
#include "settings_flags.h"

namespace isocorr::cli {
namespace {

struct SubmitArguments {
  std::string source, target;
  MatchSettings settings;
  LandmarksFile landmarks_file;
};

// A mesh argument: "meshes/{sha256}" as it is, a local file uploaded when the server lacks it.
std::string mesh_name(Connection& connection, const std::string& argument, const std::string& role) {
  if (argument.rfind("meshes/", 0) == 0) return argument;
  if (!std::filesystem::exists(argument))
    throw mesh_file_error(role, argument, "neither a mesh file nor a mesh name (meshes/{sha256})");
  return ensure_uploaded(connection, argument, role).mesh.name();
}

}  // namespace

void register_submit_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto args = std::make_shared<SubmitArguments>();
  CLI::App* cmd = add_remote_command(
      app, "submit", "create a match job and print its name at once (meshes: files or meshes/{sha256})", options,
      exit_code, [args](Connection& connection, bool json) {
        v1::CreateMatchJobRequest request;
        request.set_source_mesh(mesh_name(connection, args->source, "source"));
        request.set_target_mesh(mesh_name(connection, args->target, "target"));
        *request.mutable_settings() = api::settings_to_proto(args->settings);
        v1::Job job;
        auto context = connection.context();
        check_rpc(connection.jobs().CreateMatchJob(context.get(), request, &job), *context, "cannot create the job");
        print_line(json ? to_json(job) : job.name());
        return kExitOk;
      });
  cmd->add_option("source", args->source, "source mesh file or meshes/{sha256}")->required();
  cmd->add_option("target", args->target, "target mesh file or meshes/{sha256}")->required();
  add_match_settings_flags(*cmd, args->settings, args->landmarks_file);
}

}  // namespace isocorr::cli

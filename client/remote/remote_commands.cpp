#include "remote/remote_commands.h"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "codec/settings_codec.h"
#include "isocorr/output/map_files.h"
#include "isocorr/util/error.h"
#include "mesh_files.h"
#include "progress_printer.h"
#include "remote/job_follow.h"
#include "remote/job_output.h"
#include "remote/mesh_upload.h"
#include "remote/result_download.h"
#include "remote/rpc_error.h"
#include "settings_flags.h"

namespace isocorr::cli {
namespace {

std::atomic<bool> g_interrupted{false};
void on_interrupt(int) { g_interrupted = true; }

void print_line(const std::string& text) { std::printf("%s\n", text.c_str()); }

// A mesh argument: "meshes/{sha256}" as it is, a local file uploaded when the server lacks it.
std::string mesh_name(Connection& connection, const std::string& argument, const std::string& role) {
  if (argument.rfind("meshes/", 0) == 0) return argument;
  if (!std::filesystem::exists(argument))
    throw mesh_file_error(role, argument, "neither a mesh file nor a mesh name (meshes/{sha256})");
  return ensure_uploaded(connection, argument, role).mesh.name();
}

// Registers one subcommand with --json; `run` gets the connection and the --json flag.
CLI::App* add_command(CLI::App& app, const char* name, const char* help, ConnectionOptions& options, int& exit_code,
                      std::function<int(Connection&, bool json)> run) {
  CLI::App* cmd = app.add_subcommand(name, help);
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "print the API's JSON instead of text");
  cmd->footer("Server connection (before or after the subcommand): --server HOST:PORT (default 127.0.0.1:50051), "
              "--token-file FILE, --tls, --tls-ca PEM, --timeout S; see isocorr --help.");
  cmd->callback([&options, &exit_code, json, run] {
    exit_code = run_remote_command(*json, [&] {
      Connection connection(options);
      return run(connection, *json);
    });
  });
  return cmd;
}

}  // namespace

RemoteMatchRunner register_remote_commands(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  // upload FILE...
  auto files = std::make_shared<std::vector<std::string>>();
  add_command(app, "upload", "upload mesh files (skipped when the server has them); prints their names", options,
              exit_code, [files](Connection& connection, bool json) {
                for (const auto& file : *files) {
                  const UploadOutcome outcome = ensure_uploaded(connection, file);
                  if (json)
                    print_line("{\"mesh\":" + to_json(outcome.mesh) + ",\"uploaded\":" +
                               (outcome.uploaded ? "true" : "false") + "}");
                  else
                    print_line(describe_mesh(outcome.mesh) + (outcome.uploaded ? "" : "  (already on the server)"));
                }
                return kExitOk;
              })
      ->add_option("files", *files, "mesh files (OFF, OBJ, PLY)")->required()->check(CLI::ExistingFile);

  // submit SOURCE TARGET [settings]
  struct Submit {
    std::string source, target;
    MatchSettings settings;
  };
  auto submit = std::make_shared<Submit>();
  CLI::App* submit_cmd = add_command(
      app, "submit", "create a match job and print its name at once (meshes: files or meshes/{sha256})", options,
      exit_code, [submit](Connection& connection, bool json) {
        v1::CreateMatchJobRequest request;
        request.set_source_mesh(mesh_name(connection, submit->source, "source"));
        request.set_target_mesh(mesh_name(connection, submit->target, "target"));
        *request.mutable_settings() = api::settings_to_proto(submit->settings);
        v1::Job job;
        auto context = connection.context();
        check_rpc(connection.jobs().CreateMatchJob(context.get(), request, &job), *context, "cannot create the job");
        print_line(json ? to_json(job) : job.name());
        return kExitOk;
      });
  submit_cmd->add_option("source", submit->source, "source mesh file or meshes/{sha256}")->required();
  submit_cmd->add_option("target", submit->target, "target mesh file or meshes/{sha256}")->required();
  add_match_settings_flags(*submit_cmd, submit->settings);

  // status NAME (a job, or a mesh)
  auto status_name = std::make_shared<std::string>();
  add_command(app, "status", "show a job (jobs/ID or ID) or a mesh (meshes/SHA256)", options, exit_code,
              [status_name](Connection& connection, bool json) {
                if (status_name->rfind("meshes/", 0) == 0) {
                  v1::GetMeshRequest request;
                  request.set_name(*status_name);
                  v1::Mesh mesh;
                  auto context = connection.context();
                  check_rpc(connection.meshes().GetMesh(context.get(), request, &mesh), *context,
                            "cannot get " + *status_name);
                  print_line(json ? to_json(mesh) : describe_mesh(mesh));
                  return kExitOk;
                }
                v1::GetJobRequest request;
                request.set_name(job_name(*status_name));
                v1::Job job;
                auto context = connection.context();
                check_rpc(connection.jobs().GetJob(context.get(), request, &job), *context,
                          "cannot get " + request.name());
                print_line(json ? to_json(job) : describe_job(job));
                return kExitOk;
              })
      ->add_option("name", *status_name, "jobs/ID, ID or meshes/SHA256")->required();

  // watch JOB
  auto watch_name = std::make_shared<std::string>();
  add_command(app, "watch", "follow a job's progress until it ends (Ctrl-C cancels the job)", options, exit_code,
              [watch_name](Connection& connection, bool json) {
                std::signal(SIGINT, on_interrupt);
                ProgressPrinter printer;
                const v1::Job job = follow_job(
                    connection, job_name(*watch_name),
                    [&](const v1::Job& update) {
                      if (json)
                        print_line(to_json(update)), std::fflush(stdout);
                      else
                        printer(progress_of(update));
                    },
                    &g_interrupted);
                if (!json) print_line(describe_job(job));
                return exit_code_for_job(job);
              })
      ->add_option("job", *watch_name, "jobs/ID or ID")->required();

  // wait JOB [--wait-seconds S]
  struct Wait {
    std::string name;
    double seconds = 0;
  };
  auto wait = std::make_shared<Wait>();
  CLI::App* wait_cmd = add_command(
      app, "wait", "wait until a job ends or the time is up; exit 6 if it is still running", options, exit_code,
      [wait](Connection& connection, bool json) {
        v1::WaitJobRequest request;
        request.set_name(job_name(wait->name));
        if (wait->seconds > 0) {
          request.mutable_timeout()->set_seconds(static_cast<int64_t>(wait->seconds));
          request.mutable_timeout()->set_nanos(
              static_cast<int32_t>((wait->seconds - static_cast<int64_t>(wait->seconds)) * 1e9));
        }
        v1::Job job;
        auto context = connection.context(/*long_call=*/true);
        check_rpc(connection.jobs().WaitJob(context.get(), request, &job), *context,
                  "cannot wait for " + request.name());
        print_line(json ? to_json(job) : describe_job(job));
        return exit_code_for_job(job);
      });
  wait_cmd->add_option("job", wait->name, "jobs/ID or ID")->required();
  wait_cmd->add_option("--wait-seconds", wait->seconds, "give up after this long (0 = until the job ends)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            // Text that is no number passes here and fails the conversion with CLI11's message.
            return std::strtod(text.c_str(), nullptr) < 0 ? "must not be negative (0 waits until the job ends)" : "";
          },
          "SECONDS >= 0"));

  // cancel JOB
  auto cancel_name = std::make_shared<std::string>();
  add_command(app, "cancel", "cancel a queued or running job", options, exit_code,
              [cancel_name](Connection& connection, bool json) {
                v1::CancelJobRequest request;
                request.set_name(job_name(*cancel_name));
                v1::Job job;
                auto context = connection.context();
                check_rpc(connection.jobs().CancelJob(context.get(), request, &job), *context,
                          "cannot cancel " + request.name());
                print_line(json ? to_json(job) : describe_job(job));
                return kExitOk;
              })
      ->add_option("job", *cancel_name, "jobs/ID or ID")->required();

  // download JOB -o MAP ...
  struct Download {
    std::string name, output, reverse_output, report, confidence, reverse_confidence;
  };
  auto download = std::make_shared<Download>();
  CLI::App* download_cmd = add_command(
      app, "download", "write a finished job's maps, confidences and report", options, exit_code,
      [download](Connection& connection, bool json) {
        const Download& d = *download;
        std::vector<ResultPart> parts;
        if (!d.output.empty()) parts.push_back(ResultPart::kForwardMap);
        if (!d.reverse_output.empty()) parts.push_back(ResultPart::kReverseMap);
        if (!d.confidence.empty()) parts.push_back(ResultPart::kForwardConfidence);
        if (!d.reverse_confidence.empty()) parts.push_back(ResultPart::kReverseConfidence);
        if (!d.report.empty()) parts.push_back(ResultPart::kReport);
        if (parts.empty()) throw InputError("nothing to download: give -o, --reverse-out, --confidence-out or --report");
        const MatchOutput result = download_result(connection, job_name(d.name), parts);
        if (!d.output.empty()) write_map(d.output, result.forward);
        if (!d.reverse_output.empty()) write_map(d.reverse_output, result.reverse);
        if (!d.confidence.empty()) write_values_text(d.confidence, result.forward_confidence);
        if (!d.reverse_confidence.empty()) write_values_text(d.reverse_confidence, result.reverse_confidence);
        if (!d.report.empty()) std::ofstream(d.report) << result.report_json << '\n';
        if (json)
          print_line("{\"forward_vertices\":" + std::to_string(result.forward.size()) +
                     ",\"reverse_vertices\":" + std::to_string(result.reverse.size()) + "}");
        else
          spdlog::info("downloaded the result of {}", job_name(d.name));
        return kExitOk;
      });
  download_cmd->add_option("job", download->name, "jobs/ID or ID")->required();
  download_cmd->add_option("-o,--output", download->output, "forward map (binary if it ends in .bin)");
  download_cmd->add_option("--reverse-out", download->reverse_output, "target-to-source map");
  download_cmd->add_option("--confidence-out", download->confidence, "d_iso of each forward pair, one per line");
  download_cmd->add_option("--reverse-confidence-out", download->reverse_confidence, "the same for the reverse map");
  download_cmd->add_option("--report", download->report, "the JSON report");

  // list [jobs|meshes]
  auto what = std::make_shared<std::string>("jobs");
  add_command(app, "list", "list the server's jobs (default) or meshes", options, exit_code,
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
                    for (const auto& mesh : response.meshes()) print_line(json ? to_json(mesh) : describe_mesh(mesh));
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

  // delete MESH
  auto delete_name = std::make_shared<std::string>();
  add_command(app, "delete", "delete a mesh from the server", options, exit_code,
              [delete_name](Connection& connection, bool json) {
                v1::DeleteMeshRequest request;
                request.set_name(*delete_name);
                v1::DeleteMeshResponse response;
                auto context = connection.context();
                check_rpc(connection.meshes().DeleteMesh(context.get(), request, &response), *context,
                          "cannot delete " + *delete_name);
                print_line(json ? "{}" : "deleted " + *delete_name);
                return kExitOk;
              })
      ->add_option("mesh", *delete_name, "meshes/SHA256")->required();

  // health [--service NAME]
  auto service = std::make_shared<std::string>();
  add_command(app, "health", "ask the server's grpc.health.v1 service; exit 0 when it is serving", options, exit_code,
              [service](Connection& connection, bool json) {
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

  return [&options](const MatchJobFiles& files) -> std::optional<int> {
    if (options.server.empty()) return std::nullopt;
    return run_remote_match(options, files);
  };
}

}  // namespace isocorr::cli

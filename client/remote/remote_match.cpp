// `isocorr match SOURCE TARGET -o MAP --server HOST:PORT`: the same outputs as the local
// match, computed by isocorr-server.
#include <csignal>
#include <fstream>

#include <spdlog/spdlog.h>

#include "codec/settings_codec.h"
#include "isocorr/output/colour_transfer.h"
#include "isocorr/output/map_files.h"
#include "mesh_files.h"
#include "progress_printer.h"
#include "precise_outputs.h"
#include "remote/job_follow.h"
#include "remote/job_output.h"
#include "remote/mesh_upload.h"
#include "remote/remote_commands.h"
#include "remote/result_download.h"
#include "remote/rpc_error.h"
#include "verdict_line.h"

namespace isocorr::cli {
namespace {

std::atomic<bool> g_match_interrupted{false};
void on_match_interrupt(int) { g_match_interrupted = true; }

}  // namespace

int run_remote_match(const ConnectionOptions& options, const MatchJobFiles& files) {
  return run_remote_command(false, [&] {
    Connection connection(options);
    const UploadOutcome source = ensure_uploaded(connection, files.source, "source");
    const UploadOutcome target = ensure_uploaded(connection, files.target, "target");
    spdlog::info("source {}: {} ({})", files.source, source.mesh.name(), source.uploaded ? "uploaded" : "already on the server");
    spdlog::info("target {}: {} ({})", files.target, target.mesh.name(), target.uploaded ? "uploaded" : "already on the server");
    check_landmarks_fit(files.landmarks_file, files.settings.landmarks, source.mesh.vertex_count(),
                        target.mesh.vertex_count());

    v1::CreateMatchJobRequest request;
    request.set_source_mesh(source.mesh.name());
    request.set_target_mesh(target.mesh.name());
    *request.mutable_settings() = api::settings_to_proto(files.settings);
    v1::Job job;
    auto context = connection.context();
    check_rpc(connection.jobs().CreateMatchJob(context.get(), request, &job), *context, "cannot create the job");
    spdlog::info("job {} on {}", job.name(), connection.address());

    std::signal(SIGINT, on_match_interrupt);
    ProgressPrinter printer;
    job = follow_job_across_restarts(connection, job.name(),
                                     [&](const v1::Job& update) { printer(progress_of(update)); },
                                     &g_match_interrupted, std::chrono::seconds(options.timeout_seconds));
    if (job.state() != v1::Job::SUCCEEDED) {
      spdlog::error("{}: no map written", describe_job(job));
      return exit_code_for_job(job);
    }

    std::vector<ResultPart> parts = {ResultPart::kForwardMap};
    if (!files.reverse_output.empty() || !files.colour_ply.empty()) parts.push_back(ResultPart::kReverseMap);
    if (!files.precise_output.empty()) parts.push_back(ResultPart::kForwardPrecise);
    if (!files.reverse_precise_output.empty()) parts.push_back(ResultPart::kReversePrecise);
    if (!files.report.empty()) parts.push_back(ResultPart::kReport);
    const MatchOutput result = download_result(connection, job.name(), parts);
    write_map(files.output, result.forward);
    if (!files.reverse_output.empty()) write_map(files.reverse_output, result.reverse);
    if (!files.report.empty()) {
      std::ofstream out(files.report);
      out << result.report_json << '\n';
      if (!out) throw InputError("cannot write report '" + files.report + "'");
    }
    if (!files.colour_ply.empty())
      write_colour_ply_pair(files.colour_ply, load_mesh_file("source", files.source).mesh,
                            load_mesh_file("target", files.target).mesh, result.reverse);
    write_precise_outputs(files, result.forward_precise, result.reverse_precise);
    spdlog::info("matched {} -> {} vertices on the server: D_iso {:.4f}; map written to {}",
                 job.result().source_vertex_count(), job.result().target_vertex_count(), job.result().diso(),
                 files.output);
    log_verdict(job.result().verdict(), {job.result().verdict_reasons().begin(), job.result().verdict_reasons().end()});
    return static_cast<int>(kExitOk);
  });
}

}  // namespace isocorr::cli

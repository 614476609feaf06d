// `isocorr watch JOB`: follows a job's progress until it ends; Ctrl-C cancels the job.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "progress_printer.h"
#include "remote/job_follow.h"
#include "remote/job_output.h"
#include "remote/remote_subcommand.h"

namespace isocorr::cli {
namespace {

std::atomic<bool> g_interrupted{false};
void on_interrupt(int) { g_interrupted = true; }

}  // namespace

void register_watch_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto name = std::make_shared<std::string>();
  add_remote_command(app, "watch", "follow a job's progress until it ends (Ctrl-C cancels the job)", options,
                     exit_code, [name](Connection& connection, bool json) {
                       std::signal(SIGINT, on_interrupt);
                       ProgressPrinter printer;
                       const v1::Job job = follow_job(
                           connection, job_name(*name),
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
      ->add_option("job", *name, "jobs/ID or ID")->required();
}

}  // namespace isocorr::cli

// `isocorr cancel JOB`: cancels a queued or running job.
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "remote/job_follow.h"
#include "remote/job_output.h"
#include "remote/remote_subcommand.h"
#include "remote/rpc_error.h"

namespace isocorr::cli {

void register_cancel_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto name = std::make_shared<std::string>();
  add_remote_command(app, "cancel", "cancel a queued or running job", options, exit_code,
                     [name](Connection& connection, bool json) {
                       v1::CancelJobRequest request;
                       request.set_name(job_name(*name));
                       v1::Job job;
                       auto context = connection.context();
                       check_rpc(connection.jobs().CancelJob(context.get(), request, &job), *context,
                                 "cannot cancel " + request.name());
                       print_line(json ? to_json(job) : describe_job(job));
                       return kExitOk;
                     })
      ->add_option("job", *name, "jobs/ID or ID")->required();
}

}  // namespace isocorr::cli

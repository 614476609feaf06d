// `isocorr wait JOB [--wait-seconds S]`: waits until a job ends or the time is up.
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "remote/job_follow.h"
#include "remote/job_output.h"
#include "remote/remote_subcommand.h"
#include "remote/rpc_error.h"

namespace isocorr::cli {
namespace {

struct WaitArguments {
  std::string name;
  double seconds = 0;
};

}  // namespace

void register_wait_command(CLI::App& app, ConnectionOptions& options, int& exit_code) {
  auto args = std::make_shared<WaitArguments>();
  CLI::App* cmd = add_remote_command(
      app, "wait", "wait until a job ends or the time is up; exit 6 if it is still running", options, exit_code,
      [args](Connection& connection, bool json) {
        v1::WaitJobRequest request;
        request.set_name(job_name(args->name));
        if (args->seconds > 0) {
          request.mutable_timeout()->set_seconds(static_cast<int64_t>(args->seconds));
          request.mutable_timeout()->set_nanos(
              static_cast<int32_t>((args->seconds - static_cast<int64_t>(args->seconds)) * 1e9));
        }
        v1::Job job;
        auto context = connection.context(/*long_call=*/true);
        check_rpc(connection.jobs().WaitJob(context.get(), request, &job), *context,
                  "cannot wait for " + request.name());
        print_line(json ? to_json(job) : describe_job(job));
        return exit_code_for_job(job);
      });
  cmd->add_option("job", args->name, "jobs/ID or ID")->required();
  cmd->add_option("--wait-seconds", args->seconds, "give up after this long (0 = until the job ends)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            // Text that is no number passes here and fails the conversion with CLI11's message.
            return std::strtod(text.c_str(), nullptr) < 0 ? "must not be negative (0 waits until the job ends)" : "";
          },
          "SECONDS >= 0"));
}

}  // namespace isocorr::cli

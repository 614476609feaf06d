#include "remote/job_follow.h"

#include <chrono>
#include <thread>

#include <spdlog/spdlog.h>

#include "remote/rpc_error.h"

namespace isocorr::cli {

std::string job_name(const std::string& text) { return text.rfind("jobs/", 0) == 0 ? text : "jobs/" + text; }

v1::Job follow_job(Connection& connection, const std::string& name, const std::function<void(const v1::Job&)>& on_update,
                   const std::atomic<bool>* interrupt) {
  // The watch blocks in Read, so a helper thread turns the interrupt flag into CancelJob.
  std::atomic<bool> finished{false};
  std::thread canceller([&] {
    if (!interrupt) return;
    while (!finished) {
      if (interrupt->load()) {
        spdlog::warn("interrupted: cancelling {} on the server", name);
        v1::CancelJobRequest request;
        request.set_name(name);
        v1::Job ignored;
        connection.jobs().CancelJob(connection.context().get(), request, &ignored);
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  auto context = connection.context(/*long_call=*/true);
  v1::WatchJobRequest request;
  request.set_name(name);
  auto reader = connection.jobs().WatchJob(context.get(), request);
  v1::Job job;
  while (reader->Read(&job)) {
    on_update(job);
    if (job.done()) break;
  }
  if (!job.done()) context->TryCancel();
  const grpc::Status status = reader->Finish();
  finished = true;
  canceller.join();
  if (!job.done()) check_rpc(status.ok() ? grpc::Status(grpc::StatusCode::UNAVAILABLE, "watch ended early") : status,
                             "cannot watch " + name);
  return job;
}

}  // namespace isocorr::cli

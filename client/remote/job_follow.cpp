#include "remote/job_follow.h"

#include <algorithm>
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
  // The stream has ended either way here (the server ends it after the final state), so
  // Finish gives the server's status. (A TryCancel here would turn any error into CANCELLED.)
  const grpc::Status status = reader->Finish();
  finished = true;
  canceller.join();
  if (job.done()) return job;
  // A watch ends before its job when the server goes away: killed, or stopping (it ends or
  // cancels its open calls). The job itself is kept there, so this is "unavailable", never
  // "cancelled".
  const bool server_gone = status.ok() || status.error_code() == grpc::StatusCode::CANCELLED ||
                           status.error_code() == grpc::StatusCode::UNAVAILABLE;
  if (!server_gone) check_rpc(status, *context, "cannot watch " + name);
  throw RpcError("lost the server " + connection.address() + " while following " + name,
                 grpc::Status(grpc::StatusCode::UNAVAILABLE,
                              (status.error_code() == grpc::StatusCode::UNAVAILABLE ? status.error_message()
                                                                                    : "the watch ended early") +
                                  "; the job was not cancelled and goes on there (it is queued again when the "
                                  "server restarts): follow it with `isocorr watch " + name + " --server " +
                                  connection.address() + "`"),
                 request_id_of(*context));  // none when the server died; its id when it is stopping
}

v1::Job follow_job_across_restarts(Connection& connection, const std::string& name,
                                   const std::function<void(const v1::Job&)>& on_update,
                                   const std::atomic<bool>* interrupt, std::chrono::seconds patience) {
  for (;;) {
    try {
      return follow_job(connection, name, on_update, interrupt);
    } catch (const RpcError& lost) {
      if (lost.status().error_code() != grpc::StatusCode::UNAVAILABLE) throw;
      spdlog::warn("{}; waiting up to {} s for it to come back", lost.what(), patience.count());
      const auto deadline = std::chrono::system_clock::now() + patience;
      grpc::Status answer;
      do {
        if (interrupt && interrupt->load()) throw;
        auto context = connection.context();
        context->set_wait_for_ready(true);  // through reconnection attempts, up to the deadline
        context->set_deadline(std::min(deadline, std::chrono::system_clock::now() + std::chrono::seconds(1)));
        v1::GetJobRequest request;
        request.set_name(name);
        v1::Job job;
        answer = connection.jobs().GetJob(context.get(), request, &job);
      } while (!answer.ok() && std::chrono::system_clock::now() < deadline &&
               (answer.error_code() == grpc::StatusCode::UNAVAILABLE ||
                answer.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED));
      if (!answer.ok()) throw;
      spdlog::info("{} is back: following {} again", connection.address(), name);
    }
  }
}

}  // namespace isocorr::cli

// Following a job to its end over WatchJob, with Ctrl-C cancelling it on the server.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <string>

#include "remote/connection.h"

namespace isocorr::cli {

// Calls `on_update` with every state the server pushes and returns the final job. When
// `interrupt` becomes true, sends CancelJob once and keeps following until the job ends.
// Throws RpcError when the stream fails; UNAVAILABLE, saying that the job goes on and how
// to follow it again, when the server went away (or stopped) before the job ended.
v1::Job follow_job(Connection& connection, const std::string& name, const std::function<void(const v1::Job&)>& on_update,
                   const std::atomic<bool>* interrupt = nullptr);

// follow_job, but when the server goes away, waits up to `patience` for it to answer
// again (a restarted server has kept the job) and follows on.
v1::Job follow_job_across_restarts(Connection& connection, const std::string& name,
                                   const std::function<void(const v1::Job&)>& on_update,
                                   const std::atomic<bool>* interrupt, std::chrono::seconds patience);

// "jobs/ID" for "ID" or "jobs/ID".
std::string job_name(const std::string& text);

}  // namespace isocorr::cli

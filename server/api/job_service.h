// isocorr.v1.JobService: translates requests to the jobs and their stored results.
#pragma once

#include <atomic>

#include "api/auth.h"
#include "isocorr/v1/isocorr.grpc.pb.h"
#include "jobs/job_coordinator.h"

namespace isocorr::server {

class JobServiceImpl final : public v1::JobService::Service {
 public:
  JobServiceImpl(JobCoordinator& jobs, const TokenAuth& auth) : jobs_(jobs), auth_(auth) {}

  grpc::Status CreateMatchJob(grpc::ServerContext* context, const v1::CreateMatchJobRequest* request,
                              v1::Job* response) override;
  grpc::Status GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request, v1::Job* response) override;
  grpc::Status ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                        v1::ListJobsResponse* response) override;
  grpc::Status CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request, v1::Job* response) override;
  grpc::Status WaitJob(grpc::ServerContext* context, const v1::WaitJobRequest* request, v1::Job* response) override;
  grpc::Status WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                        grpc::ServerWriter<v1::Job>* writer) override;
  grpc::Status DownloadResult(grpc::ServerContext* context, const v1::DownloadResultRequest* request,
                              grpc::ServerWriter<v1::ResultChunk>* writer) override;

  // Ends open watches and waits with UNAVAILABLE (within a poll interval), so that their
  // clients learn the server is going away rather than that their job was cancelled.
  void stop_long_calls() { stopping_ = true; }

 private:
  JobCoordinator& jobs_;
  const TokenAuth& auth_;
  std::atomic<bool> stopping_{false};
};

}  // namespace isocorr::server

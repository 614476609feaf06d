#include "metrics/server_metrics.h"

namespace isocorr::server {
namespace {

// Seconds, from a quick job on a small mesh to an hour on a large one.
const std::vector<double> kDurationBuckets = {0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60, 120, 300, 600, 1800, 3600};

}  // namespace

ServerMetrics::ServerMetrics()
    : rpcs(registry.counter("isocorr_rpcs_total", "API calls finished, by method and gRPC status code",
                            {"method", "code"})),
      upload_bytes(registry.counter("isocorr_upload_bytes_total", "Mesh bytes received by UploadMesh").only()),
      job_duration(registry.histogram("isocorr_job_duration_seconds",
                                      "Time from a job's start to its end, by the state it ended in", {"state"},
                                      kDurationBuckets)),
      stage_duration(registry.histogram("isocorr_job_stage_duration_seconds",
                                        "Time of each stage of the succeeded jobs, as their timings report it",
                                        {"stage"}, kDurationBuckets)) {
  registry.gauge("isocorr_build_info", "Always 1; the label says which isocorr is running", {"version"})
      .with({ISOCORR_VERSION})
      .set(1);
}

ServerMetrics& server_metrics() {
  static ServerMetrics metrics;
  return metrics;
}

void record_job_durations(const JobRecord& job) {
  ServerMetrics& metrics = server_metrics();
  if (job.start_time_ms > 0)
    metrics.job_duration.with({job_state_name(job.state)}).observe((job.end_time_ms - job.start_time_ms) / 1000.0);
  if (job.state == JobState::kSucceeded)
    for (const StageTiming& timing : job.summary.timings) metrics.stage_duration.with({timing.stage}).observe(timing.seconds);
}

}  // namespace isocorr::server

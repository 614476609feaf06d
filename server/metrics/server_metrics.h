// The server's own metrics, recorded where things happen (the call guard, uploads, the job
// workers) in one process-wide registry. State that already lives elsewhere (jobs by state,
// the queue, the shape cache) is read at scrape time instead: see live_metrics.h.
#pragma once

#include "metrics/metrics_registry.h"
#include "storage/job_record.h"

namespace isocorr::server {

struct ServerMetrics {
  ServerMetrics();

  metrics::Registry registry;
  metrics::CounterFamily& rpcs;              // isocorr_rpcs_total{method,code}
  metrics::Counter& upload_bytes;            // isocorr_upload_bytes_total
  metrics::HistogramFamily& job_duration;    // isocorr_job_duration_seconds{state}
  metrics::HistogramFamily& stage_duration;  // isocorr_job_stage_duration_seconds{stage}
};

ServerMetrics& server_metrics();

// Records an ended job's duration and, when it succeeded, its stages' (whichever store ran it).
void record_job_durations(const JobRecord& job);

}  // namespace isocorr::server

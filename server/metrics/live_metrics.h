// Metrics read at scrape time from the state that already holds them: jobs by state and the
// queue (JobManager), and the shape cache's counters (ShapeCache::stats).
#pragma once

#include "jobs/job_manager.h"
#include "jobs/shape_cache.h"
#include "metrics/metrics_registry.h"

namespace isocorr::server {

void write_live_metrics(metrics::ExpositionWriter& out, const JobManager& jobs, const ShapeCache& cache);

// Everything the endpoint serves: the recorded metrics, then the live ones.
std::string metrics_text(const JobManager& jobs, const ShapeCache& cache);

}  // namespace isocorr::server

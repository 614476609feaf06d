// Metrics read at scrape time from the state that already holds them: jobs by state and the
// queue (JobCoordinator::census: this server's jobs, or all replicas' in the shared store),
// and the shape cache's counters (ShapeCache::stats).
#pragma once

#include "jobs/job_coordinator.h"
#include "jobs/shape_cache.h"
#include "metrics/metrics_registry.h"

namespace isocorr::server {

void write_live_metrics(metrics::ExpositionWriter& out, const JobCoordinator& jobs, const ShapeCache& cache);

// Everything the endpoint serves: the recorded metrics, then the live ones.
std::string metrics_text(const JobCoordinator& jobs, const ShapeCache& cache);

}  // namespace isocorr::server

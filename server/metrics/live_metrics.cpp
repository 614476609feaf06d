#include "metrics/live_metrics.h"

#include "metrics/server_metrics.h"

namespace isocorr::server {

void write_live_metrics(metrics::ExpositionWriter& out, const JobCoordinator& jobs, const ShapeCache& cache) {
  const JobCoordinator::Census census = jobs.census();
  out.family("isocorr_jobs", "Jobs the server knows (with --store, those of all replicas), by state", "gauge");
  for (JobState state : {JobState::kQueued, JobState::kRunning, JobState::kSucceeded, JobState::kFailed,
                         JobState::kCancelled}) {
    const auto it = census.by_state.find(state);
    out.sample("isocorr_jobs", {"state"}, {job_state_name(state)}, it == census.by_state.end() ? 0 : it->second);
  }
  out.family("isocorr_job_queue_length", "Jobs waiting for a worker (with --store, QUEUED jobs in the queue all replicas share)", "gauge");
  out.sample("isocorr_job_queue_length", static_cast<double>(census.queue_length));

  const ShapeCache::Stats stats = cache.stats();
  const auto counter = [&](const char* name, const char* help, int64_t value) {
    out.family(name, help, "counter");
    out.sample(name, static_cast<double>(value));
  };
  counter("isocorr_shape_cache_hits_total", "Preprocessed meshes found in the shape cache (or being built)",
          stats.hits);
  counter("isocorr_shape_cache_misses_total", "Preprocessed meshes the shape cache had to build", stats.misses);
  counter("isocorr_shape_cache_evictions_total", "Preprocessed meshes dropped to stay within --cache-bytes",
          stats.evictions);
  out.family("isocorr_shape_cache_bytes", "Memory held by the shape cache's preprocessed meshes", "gauge");
  out.sample("isocorr_shape_cache_bytes", static_cast<double>(stats.bytes));
  out.family("isocorr_shape_cache_entries", "Preprocessed meshes in the shape cache", "gauge");
  out.sample("isocorr_shape_cache_entries", static_cast<double>(stats.entries));
}

std::string metrics_text(const JobCoordinator& jobs, const ShapeCache& cache) {
  metrics::ExpositionWriter out;
  server_metrics().registry.write(out);
  write_live_metrics(out, jobs, cache);
  return out.text();
}

}  // namespace isocorr::server

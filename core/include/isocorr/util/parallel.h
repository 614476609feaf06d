// A minimal parallel loop. Each index is computed independently and writes only its own
// output, so results do not depend on the number of threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace isocorr {

// Number of worker threads to use when a setting says 0 ("all cores").
inline int resolve_thread_count(int requested) {
  if (requested > 0) return requested;
  return std::max(1u, std::thread::hardware_concurrency());
}

// Calls body(i, worker) for i in [0, count) on `threads` workers; `worker` in
// [0, threads) lets the body use per-thread scratch space. The first exception thrown by
// any body is rethrown after all workers stop.
inline void parallel_for(int count, int threads,
                         const std::function<void(int index, int worker)>& body) {
  threads = std::max(1, std::min(threads, count));
  if (threads <= 1) {
    for (int i = 0; i < count; ++i) body(i, 0);
    return;
  }
  // Indices are handed out in chunks: one shared counter bumped per index made the workers
  // fight over its cache line in loops over every vertex with a few operations each (6% of
  // a 52K-vertex match). About 64 chunks per worker still balance uneven bodies.
  const int chunk = std::max(1, count / (threads * 64));
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&](int worker) {
    for (int begin = next.fetch_add(chunk); begin < count && !failed; begin = next.fetch_add(chunk)) {
      const int end = std::min(count, begin + chunk);
      for (int i = begin; i < end && !failed; ++i) {
        try {
          body(i, worker);
        } catch (...) {
          std::lock_guard<std::mutex> lock(error_mutex);
          if (!error) error = std::current_exception();
          failed = true;
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
  work(0);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

// Calls body(i, workers) for i in [0, count) on `threads` workers, where each body may use
// `workers` threads of its own: one body per worker while a full round remains, then the
// last few side by side with the workers shared out among them. Handing every body one
// worker instead leaves the others idle for the whole of a last, lone body (three
// candidate finishings on two cores: a third of the time).
inline void parallel_for_sharing(int count, int threads, const std::function<void(int index, int workers)>& body) {
  threads = std::max(1, threads);
  const int full_rounds = count / threads * threads;
  parallel_for(full_rounds, threads, [&](int i, int) { body(i, 1); });
  const int rest = count - full_rounds;
  if (rest == 0) return;
  parallel_for(rest, rest, [&](int i, int) { body(full_rounds + i, threads / rest + (i < threads % rest ? 1 : 0)); });
}

// Calls body(i, workers) for i in [0, costly.size()) on `threads` workers, where each body
// may use `workers` threads of its own and costly[i] marks a body worth several others. The
// costly ones start first, each group in index order. Where the costly ones fill whole
// rounds of workers, the cheap ones run beside the last round, one worker each (run after
// them instead, a 5K pair's two candidate finishings and two measurings took 0.045 s
// longer). Where they do not, a lone last costly body would run on one worker while the
// cheap ones left the others idle: the costly ones share the workers first
// (parallel_for_sharing), the cheap ones after them (TOSCA 5k cat1 -> cat2, three
// finishings and one measuring: a core sat idle for 0.2 s). Where all bodies are alike
// (all costly, or none), the last few share the workers.
inline void parallel_for_costly_first(const std::vector<bool>& costly, int threads,
                                      const std::function<void(int index, int workers)>& body) {
  threads = std::max(1, threads);
  std::vector<int> order;
  for (size_t i = 0; i < costly.size(); ++i)
    if (costly[i]) order.push_back(static_cast<int>(i));
  const int costly_count = static_cast<int>(order.size());
  for (size_t i = 0; i < costly.size(); ++i)
    if (!costly[i]) order.push_back(static_cast<int>(i));
  const int count = static_cast<int>(order.size());
  if (costly_count == count || costly_count == 0 || costly_count % threads != 0) {
    parallel_for_sharing(costly_count, threads, [&](int k, int workers) { body(order[k], workers); });
    parallel_for_sharing(count - costly_count, threads,
                         [&](int k, int workers) { body(order[costly_count + k], workers); });
  } else {
    parallel_for(count, threads, [&](int k, int) { body(order[k], 1); });
  }
}

}  // namespace isocorr

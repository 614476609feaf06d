// Preprocessed meshes shared by all jobs, bounded in bytes (PreprocessedShape::memory_bytes)
// with least-recently-used eviction. Two jobs asking for the same key while it is being
// built wait for the one build (a shared future per key) instead of computing it twice.
#pragma once

#include <cstdint>
#include <functional>
#include <future>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

#include "isocorr/shape/preprocessed_shape.h"

namespace isocorr::server {

class ShapeCache {
 public:
  using ShapePtr = std::shared_ptr<const PreprocessedShape>;
  using Builder = std::function<ShapePtr()>;

  explicit ShapeCache(int64_t capacity_bytes) : capacity_bytes_(capacity_bytes) {}

  // Key: mesh digest + "|" + PreprocessOptions::key(). Runs `build` when nobody has the key
  // (or is building it); otherwise waits for that build. A failed build is forgotten and
  // its exception goes to everyone waiting on it (a waiter whose own job was not
  // cancelled retries when the builder's job was).
  ShapePtr get_or_build(const std::string& key, const Builder& build);

  enum class MeshState { kAbsent, kBuilding, kReady };
  // Over every options key of one mesh digest.
  MeshState state_of_mesh(const std::string& digest) const;

  struct Stats {
    int64_t hits = 0, misses = 0, bytes = 0, entries = 0, evictions = 0;
  };
  Stats stats() const;

 private:
  struct Entry {
    std::shared_future<ShapePtr> future;
    bool ready = false;
    int64_t bytes = 0;
    std::list<std::string>::iterator lru;  // valid when ready
  };
  void evict_locked();

  const int64_t capacity_bytes_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, Entry> entries_;
  std::list<std::string> lru_;  // most recently used first; ready entries only
  Stats stats_;
};

}  // namespace isocorr::server

#include "jobs/shape_cache.h"

namespace isocorr::server {

ShapeCache::ShapePtr ShapeCache::get_or_build(const std::string& key, const Builder& build) {
  std::unique_lock lock(mutex_);
  if (auto it = entries_.find(key); it != entries_.end()) {
    ++stats_.hits;
    Entry& entry = it->second;
    if (entry.ready) lru_.splice(lru_.begin(), lru_, entry.lru);
    std::shared_future<ShapePtr> future = entry.future;
    lock.unlock();
    return future.get();  // rethrows the builder's exception
  }
  ++stats_.misses;
  std::promise<ShapePtr> promise;
  entries_[key].future = promise.get_future().share();
  lock.unlock();

  ShapePtr shape;
  try {
    shape = build();
  } catch (...) {
    lock.lock();
    entries_.erase(key);
    lock.unlock();
    promise.set_exception(std::current_exception());
    throw;
  }
  lock.lock();
  Entry& entry = entries_[key];
  entry.ready = true;
  entry.bytes = static_cast<int64_t>(shape->memory_bytes());
  lru_.push_front(key);
  entry.lru = lru_.begin();
  stats_.bytes += entry.bytes;
  evict_locked();
  lock.unlock();
  promise.set_value(shape);
  return shape;
}

void ShapeCache::evict_locked() {
  // Oldest first. The new entry sits at the front, so it goes last, and only when it alone
  // exceeds the capacity (its caller still gets the shape: the jobs holding it keep it alive).
  while (stats_.bytes > capacity_bytes_ && !lru_.empty()) {
    const std::string victim = lru_.back();
    lru_.pop_back();
    stats_.bytes -= entries_[victim].bytes;
    entries_.erase(victim);
    ++stats_.evictions;
  }
}

ShapeCache::MeshState ShapeCache::state_of_mesh(const std::string& digest) const {
  std::lock_guard lock(mutex_);
  MeshState state = MeshState::kAbsent;
  const std::string prefix = digest + "|";
  for (const auto& [key, entry] : entries_) {
    if (key.compare(0, prefix.size(), prefix) != 0) continue;
    if (entry.ready) return MeshState::kReady;
    state = MeshState::kBuilding;
  }
  return state;
}

ShapeCache::Stats ShapeCache::stats() const {
  std::lock_guard lock(mutex_);
  Stats stats = stats_;
  stats.entries = static_cast<int64_t>(lru_.size());
  return stats;
}

}  // namespace isocorr::server

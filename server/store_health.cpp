#include "store_health.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>

#include <pqxx/pqxx>
#include <spdlog/spdlog.h>

#include "isocorr/v1/isocorr.grpc.pb.h"

namespace isocorr::server {
namespace {

constexpr auto kProbeInterval = std::chrono::seconds(1);
// Seconds a connection attempt may take: a store that does not answer is as down as one
// that refuses.
constexpr const char* kConnectTimeout = "connect_timeout=2";

// `url` (a postgresql:// URI or key=value words) with the connection timeout, unless it sets one.
std::string with_connect_timeout(const std::string& url) {
  if (url.empty() || url.find("connect_timeout") != std::string::npos) return url;
  if (url.find("://") == std::string::npos) return url + " " + kConnectTimeout;
  return url + (url.find('?') == std::string::npos ? "?" : "&") + kConnectTimeout;
}

}  // namespace

StoreHealth::StoreHealth(const ServerOptions& options, grpc::HealthCheckServiceInterface& health)
    : data_dir_(options.data_dir),
      postgres_url_(with_connect_timeout(options.store)),
      health_(health) {
  health_.SetServingStatus(kLivenessService, true);
  set_serving(true);  // the store was just opened
  thread_ = std::thread([this] { run(); });
}

StoreHealth::~StoreHealth() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void StoreHealth::run() {
  bool serving = true;
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, kProbeInterval, [this] { return stopping_; })) {
    lock.unlock();
    const std::string problem = probe();
    lock.lock();
    if (stopping_ || problem.empty() == serving) continue;
    serving = problem.empty();
    set_serving(serving);
    if (serving)
      spdlog::info("store reachable again: health SERVING");
    else
      spdlog::warn("store unreachable, health NOT_SERVING until it is back: {}", problem);
  }
}

void StoreHealth::set_serving(bool serving) {
  for (const std::string& service : {std::string(), std::string(v1::MeshService::service_full_name()),
                                     std::string(v1::JobService::service_full_name())})
    health_.SetServingStatus(service, serving);
}

std::string StoreHealth::probe() {
  if (!postgres_url_.empty()) return probe_postgres();
  std::error_code error;
  if (!std::filesystem::is_directory(data_dir_, error)) return "the data directory " + data_dir_ + " is gone";
  if (access(data_dir_.c_str(), W_OK | X_OK) != 0) return "the data directory " + data_dir_ + " is not writable";
  return "";
}

std::string StoreHealth::probe_postgres() {
  // A connection broken by a restart of the database fails once: then a new one is tried.
  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool reused = connection_ != nullptr;
    try {
      if (!connection_) connection_ = std::make_unique<pqxx::connection>(postgres_url_);
      pqxx::nontransaction query(*connection_);
      query.exec("SELECT 1");
      return "";
    } catch (const std::exception& e) {
      connection_.reset();
      if (!reused) {
        std::string message = e.what();  // libpq's end in a newline; the log line must not
        while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) message.pop_back();
        std::replace(message.begin(), message.end(), '\n', ' ');
        return "PostgreSQL: " + message;
      }
    }
  }
  return "PostgreSQL cannot be reached";
}

}  // namespace isocorr::server

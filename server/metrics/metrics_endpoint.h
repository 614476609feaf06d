// The Prometheus scrape endpoint: GET /metrics over HTTP, served by civetweb (Debian's
// libcivetweb) on its own small thread pool, apart from the gRPC port.
#pragma once

#include <functional>
#include <string>

struct mg_context;

namespace isocorr::server {

// "HOST:PORT", ":PORT" or "PORT" (no host: loopback) as civetweb's "IP:PORT"; "localhost"
// is 127.0.0.1. Throws std::invalid_argument naming what is wrong.
std::string metrics_listen_address(const std::string& listen);

class MetricsEndpoint {
 public:
  using Render = std::function<std::string()>;  // the exposition text, called per scrape

  // Listens at once; throws std::runtime_error when it cannot (port taken, bad address).
  MetricsEndpoint(const std::string& listen, Render render);
  ~MetricsEndpoint();
  MetricsEndpoint(const MetricsEndpoint&) = delete;
  MetricsEndpoint& operator=(const MetricsEndpoint&) = delete;

  int port() const { return port_; }  // the bound one (for port 0)
  const std::string& address() const { return address_; }

 private:
  Render render_;
  std::string address_;
  mg_context* context_ = nullptr;
  int port_ = 0;
};

}  // namespace isocorr::server

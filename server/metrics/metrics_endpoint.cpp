#include "metrics/metrics_endpoint.h"

#include <civetweb.h>

#include <cstring>
#include <stdexcept>

#include <spdlog/spdlog.h>

namespace isocorr::server {
namespace {

constexpr const char* kContentType = "text/plain; version=0.0.4; charset=utf-8";

bool all_digits(const std::string& text) {
  return !text.empty() && text.size() <= 5 && text.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

std::string metrics_listen_address(const std::string& listen) {
  const size_t colon = listen.rfind(':');
  std::string host = colon == std::string::npos ? "" : listen.substr(0, colon);
  const std::string port = colon == std::string::npos ? listen : listen.substr(colon + 1);
  if (!all_digits(port) || std::stoi(port) > 65535)
    throw std::invalid_argument("--metrics-listen wants HOST:PORT or PORT, got '" + listen + "'");
  if (host.empty() || host == "localhost") host = "127.0.0.1";
  // Debian's civetweb is built without IPv6, and it binds addresses, not names.
  if (host.find_first_not_of("0123456789.") != std::string::npos)
    throw std::invalid_argument("--metrics-listen takes an IPv4 address (or localhost), got '" + host + "'");
  return host + ":" + port;
}

MetricsEndpoint::MetricsEndpoint(const std::string& listen, Render render)
    : render_(std::move(render)), address_(metrics_listen_address(listen)) {
  mg_init_library(0);
  // No document_root: civetweb serves no files, only the handler below (404 elsewhere).
  const char* options[] = {"listening_ports", address_.c_str(), "num_threads", "2", nullptr};
  mg_init_data init{};
  init.configuration_options = options;
  char error_text[256] = {0};
  mg_error_data error{};
  error.text = error_text;
  error.text_buffer_size = sizeof error_text;
  context_ = mg_start2(&init, &error);
  if (!context_) {
    mg_exit_library();
    throw std::runtime_error("cannot serve metrics on " + address_ + ": " + error_text);
  }
  mg_set_request_handler(
      context_, "/metrics$",
      [](mg_connection* connection, void* self) {
        const mg_request_info* request = mg_get_request_info(connection);
        if (std::strcmp(request->request_method, "GET") != 0 && std::strcmp(request->request_method, "HEAD") != 0) {
          mg_send_http_error(connection, 405, "only GET /metrics");
          return 405;
        }
        std::string body;
        try {
          body = static_cast<MetricsEndpoint*>(self)->render_();
        } catch (const std::exception& e) {
          spdlog::error("metrics: {}", e.what());
          mg_send_http_error(connection, 500, "metrics unavailable; the server log says why");
          return 500;
        }
        mg_send_http_ok(connection, kContentType, static_cast<long long>(body.size()));
        if (std::strcmp(request->request_method, "GET") == 0) mg_write(connection, body.data(), body.size());
        return 200;
      },
      this);
  mg_server_port port{};
  if (mg_get_server_ports(context_, 1, &port) == 1) port_ = port.port;
  spdlog::info("metrics on http://{}:{}/metrics", address_.substr(0, address_.rfind(':')), port_);
}

MetricsEndpoint::~MetricsEndpoint() {
  mg_stop(context_);
  mg_exit_library();
}

}  // namespace isocorr::server

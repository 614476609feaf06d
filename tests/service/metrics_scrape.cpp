#include "metrics_scrape.h"

#include <civetweb.h>

namespace isocorr::testing {

std::pair<int, std::string> http_get(int port, const std::string& path) {
  [[maybe_unused]] static const unsigned initialised = mg_init_library(0);  // once, as civetweb asks
  char error[256] = {0};
  mg_connection* connection = mg_download("127.0.0.1", port, 0, error, sizeof error,
                                          "GET %s HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n", path.c_str());
  if (!connection) return {-1, error};
  const int status = mg_get_response_info(connection)->status_code;
  std::string body;
  char buffer[8192];
  for (int n; (n = mg_read(connection, buffer, sizeof buffer)) > 0;) body.append(buffer, n);
  mg_close_connection(connection);
  return {status, body};
}

double sample(const std::string& exposition, const std::string& series) {
  const std::string prefix = "\n" + series + " ";
  const size_t at = ("\n" + exposition).find(prefix);
  if (at == std::string::npos) return -1;
  return std::stod(exposition.substr(at + prefix.size() - 1));
}

}  // namespace isocorr::testing

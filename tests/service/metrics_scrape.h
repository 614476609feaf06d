// Reading a server's Prometheus endpoint in the service tests, with civetweb's own client.
#pragma once

#include <string>
#include <utility>

namespace isocorr::testing {

// GET http://127.0.0.1:port/path; the status code and the body (-1 and the reason when the
// connection fails).
std::pair<int, std::string> http_get(int port, const std::string& path);

// The value of one series ("name{labels}" exactly as exposed), or -1 when it is absent.
double sample(const std::string& exposition, const std::string& series);

}  // namespace isocorr::testing

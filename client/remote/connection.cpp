#include "remote/connection.h"

#include <cctype>
#include <fstream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "isocorr/util/error.h"

namespace isocorr::cli {
namespace {

std::string read_text(const std::string& path, const char* what) {
  std::ifstream in(path);
  if (!in) throw InputError(std::string("cannot read ") + what + " '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

void add_connection_flags(CLI::App& app, ConnectionOptions& o) {
  const char* group = "Server connection";
  app.add_option("--server", o.server, "HOST:PORT of isocorr-server (match runs there instead of in-process; "
                 "other remote commands default to 127.0.0.1:50051)")->group(group);
  app.add_option("--token-file", o.token_file, "file holding the server's bearer token")->group(group)
      ->check(CLI::ExistingFile);
  app.add_flag("--tls", o.tls, "connect with TLS, trusting the system's root certificates")->group(group);
  app.add_option("--tls-ca", o.tls_ca, "connect with TLS, trusting this PEM root certificate")->group(group)
      ->check(CLI::ExistingFile);
  app.add_option("--timeout", o.timeout_seconds, "deadline in seconds of short calls")->group(group)
      ->capture_default_str();
}

Connection::Connection(const ConnectionOptions& options)
    : address_(options.server.empty() ? ConnectionOptions::kDefaultServer : options.server),
      timeout_seconds_(options.timeout_seconds) {
  if (!options.token_file.empty()) {
    token_ = read_text(options.token_file, "token file");
    while (!token_.empty() && std::isspace(static_cast<unsigned char>(token_.back()))) token_.pop_back();
  }
  std::shared_ptr<grpc::ChannelCredentials> credentials = grpc::InsecureChannelCredentials();
  if (options.tls || !options.tls_ca.empty()) {
    grpc::SslCredentialsOptions ssl;
    if (!options.tls_ca.empty()) ssl.pem_root_certs = read_text(options.tls_ca, "TLS root certificate");
    credentials = grpc::SslCredentials(ssl);
  }
  channel_ = grpc::CreateChannel(address_, credentials);
  meshes_ = v1::MeshService::NewStub(channel_);
  jobs_ = v1::JobService::NewStub(channel_);
  health_ = grpc::health::v1::Health::NewStub(channel_);
}

std::unique_ptr<grpc::ClientContext> Connection::context(bool long_call) const {
  auto context = std::make_unique<grpc::ClientContext>();
  if (!token_.empty()) context->AddMetadata("authorization", "Bearer " + token_);
  if (!long_call)
    context->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(timeout_seconds_));
  return context;
}

}  // namespace isocorr::cli

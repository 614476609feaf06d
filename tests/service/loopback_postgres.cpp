#include "loopback_postgres.h"

#include <netinet/in.h>
#include <pwd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
#include <stdexcept>

namespace isocorr::testing {
namespace fs = std::filesystem;

namespace {

constexpr const char* kUnprivilegedUser = "nobody";
constexpr const char* kDatabaseUser = "isocorr";

// A port the kernel just gave out and took back; postgres binds it right after.
int free_loopback_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0)
    port = ntohs(address.sin_port);
  close(fd);
  return port;
}

std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

fs::path LoopbackPostgres::find_binaries() {
  fs::path best;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator("/usr/lib/postgresql", error)) {
    const fs::path bin = entry.path() / "bin";
    if (fs::exists(bin / "initdb") && fs::exists(bin / "pg_ctl") && fs::exists(bin / "psql") &&
        (best.empty() || std::stoi(entry.path().filename().string()) >
                             std::stoi(best.parent_path().filename().string())))
      best = bin;
  }
  return best;
}

std::string LoopbackPostgres::as_owner(const std::string& command) const {
  return geteuid() == 0 ? "runuser -u " + std::string(kUnprivilegedUser) + " -- " + command : command;
}

LoopbackPostgres::LoopbackPostgres(const fs::path& bin_dir) : bin_(bin_dir) {
  dir_ = fs::temp_directory_path() / ("isocorr_pg_" + std::to_string(getpid()));
  fs::remove_all(dir_);
  fs::create_directories(dir_);
  if (geteuid() == 0) {
    const passwd* owner = getpwnam(kUnprivilegedUser);
    if (!owner || chown(dir_.c_str(), owner->pw_uid, owner->pw_gid) != 0)
      throw std::runtime_error("cannot hand the cluster directory to user " + std::string(kUnprivilegedUser));
  }
  const fs::path data = dir_ / "data", log = dir_ / "postgres.log";
  const CommandRun init = run_command(as_owner((bin_ / "initdb").string() + " -D " + data.string() + " -U " +
                                               kDatabaseUser + " --auth=trust --no-sync -E UTF8"));
  if (init.exit_code != 0) throw std::runtime_error("initdb failed: " + init.err + init.out);
  // A port taken between the probe and the bind makes the start fail: try another.
  for (int attempt = 0; attempt < 5 && !started_; ++attempt) {
    port_ = free_loopback_port();
    start();
  }
  if (!started_) throw std::runtime_error("postgres did not start: " + slurp_file(log));
}

LoopbackPostgres::~LoopbackPostgres() {
  stop();
  std::error_code ignored;
  fs::remove_all(dir_, ignored);
}

CommandRun LoopbackPostgres::pg_ctl(const std::string& arguments) const {
  return run_command(as_owner((bin_ / "pg_ctl").string() + " -D " + (dir_ / "data").string() + " " + arguments));
}

bool LoopbackPostgres::start() {
  if (!started_) {
    const std::string options = "-p " + std::to_string(port_) + " -k " + dir_.string() +
                                " -c listen_addresses=127.0.0.1 -c fsync=off";
    started_ = pg_ctl("-l " + (dir_ / "postgres.log").string() + " -o " + quoted(options) + " -t 60 -w start")
                   .exit_code == 0;
  }
  return started_;
}

bool LoopbackPostgres::stop() {
  if (started_) started_ = pg_ctl("-m immediate -t 60 -w stop").exit_code != 0;
  return !started_;
}

std::string LoopbackPostgres::url(const std::string& database) const {
  // Through the unix socket: libpq then tries neither TLS nor GSSAPI encryption first, so
  // the clients under test load neither library's state (which LeakSanitizer would see).
  return "postgresql://" + std::string(kDatabaseUser) + "@/" + database + "?host=" + dir_.string() +
         "&port=" + std::to_string(port_);
}

void LoopbackPostgres::create_database(const std::string& name) const {
  const CommandRun created = sql("postgres", "CREATE DATABASE " + name);
  if (created.exit_code != 0) throw std::runtime_error("cannot create database " + name + ": " + created.err);
}

CommandRun LoopbackPostgres::sql(const std::string& database, const std::string& statement) const {
  return run_command((bin_ / "psql").string() + " " + quoted(url(database)) + " -v ON_ERROR_STOP=1 -At -c " +
                     quoted(statement));
}

LoopbackPostgres* LoopbackPostgresTest::postgres_ = nullptr;

void LoopbackPostgresTest::SetUpTestSuite() {
  const fs::path bin = LoopbackPostgres::find_binaries();
  if (!bin.empty()) postgres_ = new LoopbackPostgres(bin);
}

void LoopbackPostgresTest::TearDownTestSuite() {
  delete postgres_;
  postgres_ = nullptr;
}

void LoopbackPostgresTest::SetUp() {
  if (!postgres_)
    GTEST_SKIP() << "no PostgreSQL server binaries in /usr/lib/postgresql/*/bin (Debian package `postgresql`, "
                    "listed in deploy/packages.txt): the shared-store tests cannot run here";
  database_ = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  for (char& c : database_) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  postgres_->create_database(database_);
}

}  // namespace isocorr::testing

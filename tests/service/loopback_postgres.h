// A throw-away PostgreSQL server for the replica tests: initdb into a temporary directory,
// postgres on a free loopback port and a unix socket in that directory (which the clients
// use), stopped and removed at the end. Uses Debian's binaries in /usr/lib/postgresql/<version>/bin. As
// initdb and postgres refuse to run as root, under root they run as the user `nobody`
// (runuser), owning the temporary directory.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "server_process.h"

namespace isocorr::testing {

class LoopbackPostgres {
 public:
  // The bin directory of the newest PostgreSQL installed, or empty when there is none.
  static std::filesystem::path find_binaries();

  // Starts the server (bounded waits); throws std::runtime_error with its log on failure.
  explicit LoopbackPostgres(const std::filesystem::path& bin_dir);
  ~LoopbackPostgres();
  LoopbackPostgres(const LoopbackPostgres&) = delete;
  LoopbackPostgres& operator=(const LoopbackPostgres&) = delete;

  // libpq URI of a database (created with create_database), for isocorr-server --store.
  std::string url(const std::string& database = "postgres") const;
  void create_database(const std::string& name) const;  // throws std::runtime_error
  // Runs one SQL statement with psql; the rows unaligned, one a line, fields split by '|'.
  CommandRun sql(const std::string& database, const std::string& statement) const;

  // Stops the server as an outage would (connections cut, nothing flushed), and starts it
  // again on the same port and socket; both wait (bounded) and return whether they succeeded.
  bool stop();
  bool start();

 private:
  // `command` as the user that owns the cluster.
  std::string as_owner(const std::string& command) const;
  CommandRun pg_ctl(const std::string& arguments) const;

  std::filesystem::path bin_, dir_;
  int port_ = 0;
  bool started_ = false;
};

// Tests on a loopback PostgreSQL: one server per test suite, a database of its own per test
// (named after the test); skipped with a clear message where the binaries are absent.
class LoopbackPostgresTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite();
  static void TearDownTestSuite();
  void SetUp() override;

  // The test's database.
  std::string database_url() const { return postgres_->url(database_); }
  CommandRun sql(const std::string& statement) const { return postgres_->sql(database_, statement); }

  static LoopbackPostgres* postgres_;  // null when the binaries are absent
  std::string database_;
};

}  // namespace isocorr::testing

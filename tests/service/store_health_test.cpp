// grpc.health.v1 follows the store: NOT_SERVING while PostgreSQL is stopped or the data
// directory is gone, SERVING again once it is back. The real server, client and PostgreSQL
// on loopback; every wait polls with a generous bound, so a loaded machine only slows it.
#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "loopback_postgres.h"
#include "server_process.h"

namespace isocorr::testing {
namespace {

namespace fs = std::filesystem;

// Polls `isocorr health` (bounded: two minutes) until it prints `status`.
bool health_becomes(const ServerProcess& server, const std::string& status, const std::string& service = "") {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (std::chrono::steady_clock::now() < deadline) {
    if (server.client("health --timeout 10 --service '" + service + "'").out == status + "\n") return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return false;
}

fs::path test_dir() {
  return fs::temp_directory_path() / ("isocorr_store_health_test_" + std::to_string(getpid()) + "_" +
                                      ::testing::UnitTest::GetInstance()->current_test_info()->name());
}

class StoreHealth : public LoopbackPostgresTest {};

TEST_F(StoreHealth, NotServingWhilePostgresIsStopped) {
  const fs::path dir = test_dir();
  fs::remove_all(dir);
  {
    ServerProcess server(dir, {"--store", database_url()});
    ASSERT_TRUE(health_becomes(server, "SERVING"));
    ASSERT_TRUE(postgres_->stop());
    const bool down = health_becomes(server, "NOT_SERVING");
    const bool job_service_down = health_becomes(server, "NOT_SERVING", "isocorr.v1.JobService");
    const CommandRun alive = server.client("health --service liveness");
    // Asked while PostgreSQL is still stopped: once it is back, the answer may already be SERVING.
    const int exit_code_while_down = server.client("health").exit_code;
    const bool restarted = postgres_->start();  // before any assertion ends the test: the suite shares it
    ASSERT_TRUE(restarted);
    EXPECT_TRUE(down) << slurp_file(server.log_path());
    EXPECT_TRUE(job_service_down);
    EXPECT_EQ(alive.out, "SERVING\n") << alive.err;  // a liveness probe must not restart it
    EXPECT_EQ(exit_code_while_down, down ? 3 : 0);
    EXPECT_TRUE(health_becomes(server, "SERVING")) << slurp_file(server.log_path());
    EXPECT_EQ(server.client("health").exit_code, 0);
    EXPECT_EQ(server.client("list").exit_code, 0);  // and the data calls work again
    const std::string log = slurp_file(server.log_path());
    EXPECT_NE(log.find("health NOT_SERVING"), std::string::npos) << log;
    EXPECT_NE(log.find("health SERVING"), std::string::npos) << log;
  }
  fs::remove_all(dir);
}

// The file store is down only when its directory is: gone (moved away) and back.
TEST(StoreHealthFiles, NotServingWhileTheDataDirectoryIsGone) {
  const fs::path dir = test_dir(), data = dir / "data", moved = dir / "moved";
  fs::remove_all(dir);
  {
    ServerProcess server(data);
    ASSERT_TRUE(health_becomes(server, "SERVING"));
    fs::rename(data, moved);
    const bool down = health_becomes(server, "NOT_SERVING");
    fs::rename(moved, data);
    EXPECT_TRUE(down) << slurp_file(server.log_path());
    EXPECT_TRUE(health_becomes(server, "SERVING")) << slurp_file(server.log_path());
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace isocorr::testing

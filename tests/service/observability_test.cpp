// What an operator sees of a running isocorr-server: the Prometheus endpoint (jobs, the
// shape cache, calls by status code) and the request id that each response carries back
// to the client, its errors and --verbose, and the server's log lines.
#include <filesystem>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/procedural_meshes.h"
#include "client_json.h"
#include "metrics_scrape.h"
#include "server_process.h"
#include "suite_files.h"

namespace isocorr::testing {
namespace {

namespace fs = std::filesystem;

class Observability : public WithSuiteFiles<Observability> {
 protected:
  static void SetUpTestSuite() {
    make_suite_dir("isocorr_observability_test");
    const TriangleMesh creature = limbed_blob(3);
    write_ply(path("creature.ply").string(), creature);
    write_ply(path("creature_moved.ply").string(), rotated_scaled_renumbered(creature, 1.3, 7).mesh);
  }

  // A server with its metrics on a free loopback port.
  struct Observed {
    explicit Observed(const fs::path& data_dir)
        : server(data_dir, {"--metrics-listen", "127.0.0.1:0", "--metrics-port-file", data_dir.string() + ".mport"}),
          metrics_port(std::stoi(slurp_file(data_dir.string() + ".mport"))) {}
    std::string scrape() const {
      const auto [status, body] = http_get(metrics_port, "/metrics");
      EXPECT_EQ(status, 200) << body;
      return body;
    }
    ServerProcess server;
    int metrics_port;
  };

  std::string submit_and_wait(const ServerProcess& server) {
    const CommandRun submit =
        server.client("submit " + path("creature.ply").string() + " " + path("creature_moved.ply").string());
    EXPECT_EQ(submit.exit_code, 0) << submit.err;
    const std::string job = submit.out.substr(0, submit.out.find('\n'));
    const CommandRun wait = server.client("wait " + job + " --json");
    EXPECT_EQ(last_json(wait)["state"], "SUCCEEDED") << wait.out << wait.err;
    return job;
  }
};

TEST_F(Observability, MetricsCountJobsCacheHitsAndCallsByCode) {
  Observed observed(data_dir());
  const std::string before = observed.scrape();
  EXPECT_NE(before.find("# TYPE isocorr_rpcs_total counter\n"), std::string::npos);
  EXPECT_EQ(sample(before, "isocorr_build_info{version=\"" ISOCORR_VERSION "\"}"), 1);
  EXPECT_EQ(sample(before, "isocorr_jobs{state=\"SUCCEEDED\"}"), 0);

  submit_and_wait(observed.server);
  const std::string first = observed.scrape();
  EXPECT_EQ(sample(first, "isocorr_jobs{state=\"SUCCEEDED\"}"), 1);
  EXPECT_EQ(sample(first, "isocorr_job_queue_length"), 0);
  EXPECT_EQ(sample(first, "isocorr_job_duration_seconds_count{state=\"SUCCEEDED\"}"), 1);
  EXPECT_EQ(sample(first, "isocorr_job_duration_seconds_bucket{state=\"SUCCEEDED\",le=\"+Inf\"}"), 1);
  EXPECT_EQ(sample(first, "isocorr_job_stage_duration_seconds_count{stage=\"tracking\"}"), 1);
  EXPECT_EQ(sample(first, "isocorr_shape_cache_misses_total"), 2);  // source and target
  EXPECT_EQ(sample(first, "isocorr_shape_cache_hits_total"), 0);
  EXPECT_GT(sample(first, "isocorr_shape_cache_bytes"), 0);
  EXPECT_EQ(sample(first, "isocorr_upload_bytes_total"),
            static_cast<double>(fs::file_size(path("creature.ply")) + fs::file_size(path("creature_moved.ply"))));
  EXPECT_EQ(sample(first, "isocorr_rpcs_total{method=\"UploadMesh\",code=\"OK\"}"), 2);
  EXPECT_EQ(sample(first, "isocorr_rpcs_total{method=\"CreateMatchJob\",code=\"OK\"}"), 1);

  // The same meshes again: both preprocessed shapes come from the cache.
  submit_and_wait(observed.server);
  const std::string second = observed.scrape();
  EXPECT_EQ(sample(second, "isocorr_jobs{state=\"SUCCEEDED\"}"), 2);
  EXPECT_EQ(sample(second, "isocorr_shape_cache_hits_total"), 2);
  EXPECT_EQ(sample(second, "isocorr_shape_cache_misses_total"), 2);
  EXPECT_EQ(sample(second, "isocorr_job_duration_seconds_count{state=\"SUCCEEDED\"}"), 2);

  EXPECT_EQ(observed.server.client("status jobs/0123456789abcdef").exit_code, 2);
  EXPECT_EQ(sample(observed.scrape(), "isocorr_rpcs_total{method=\"GetJob\",code=\"NOT_FOUND\"}"), 1);

  EXPECT_EQ(http_get(observed.metrics_port, "/elsewhere").first, 404);
}

TEST_F(Observability, MetricsEndpointIsOffUnlessAskedAndRefusesABadAddress) {
  ServerProcess plain(data_dir());
  EXPECT_EQ(slurp_file(plain.log_path()).find("metrics on"), std::string::npos);
  EXPECT_THROW(ServerProcess(data_dir() / "bad", {"--metrics-listen", "metrics.example:9464"}), std::runtime_error);
}

TEST_F(Observability, RequestIdsReachTheClientAndTheLogs) {
  ServerProcess server(data_dir());
  // In an error message, as text and as JSON, and in the server's line for that call.
  const CommandRun missing = server.client("status jobs/0123456789abcdef");
  EXPECT_EQ(missing.exit_code, 2);
  std::smatch id;
  ASSERT_TRUE(std::regex_search(missing.err, id, std::regex(R"(\(request (r[0-9]+)\))"))) << missing.err;
  EXPECT_NE(slurp_file(server.log_path()).find("[" + id[1].str() + "] GetJob -> 5 "), std::string::npos);
  const CommandRun missing_json = server.client("status jobs/0123456789abcdef --json");
  const std::string json_id = last_json(missing_json)["error"].value("request_id", "");
  EXPECT_TRUE(std::regex_match(json_id, std::regex("r[0-9]+"))) << missing_json.out;
  EXPECT_NE(json_id, id[1].str());

  // With --verbose, every call's id; the job's log lines name the call that created it.
  const CommandRun submit = server.client("--verbose submit " + path("creature.ply").string() + " " +
                                          path("creature_moved.ply").string());
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  std::string create_id;
  const std::regex verbose_line(R"(server request (r[0-9]+): OK)");
  for (std::sregex_iterator it(submit.err.begin(), submit.err.end(), verbose_line), end; it != end; ++it)
    create_id = (*it)[1];  // CreateMatchJob is the last call
  ASSERT_FALSE(create_id.empty()) << submit.err;
  const std::string job = submit.out.substr(0, submit.out.find('\n'));
  EXPECT_EQ(last_json(server.client("wait " + job + " --json"))["state"], "SUCCEEDED");
  const std::string log = slurp_file(server.log_path());
  const std::string tag = "[job " + job.substr(job.find('/') + 1) + " from " + create_id + "] ";
  EXPECT_NE(log.find(tag + "queued"), std::string::npos) << log;
  EXPECT_NE(log.find(tag + "succeeded"), std::string::npos) << log;
  EXPECT_NE(log.find("[" + create_id + "] CreateMatchJob ok"), std::string::npos);
}

}  // namespace
}  // namespace isocorr::testing

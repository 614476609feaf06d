// Two isocorr-server replicas on one real PostgreSQL store (--store), on loopback: a mesh
// uploaded through one is matched through the other and downloaded through either; a
// replica killed with SIGKILL in the middle of a job loses nothing, as the other takes the
// job over once its lease expires; a cancel reaches the job through any replica; the
// database's bytes are checked on every read (DATA_LOSS); each replica's metrics count the
// shared store's jobs and the jobs it ran. Skipped only where Debian's
// PostgreSQL binaries are absent (package `postgresql`, in deploy/packages.txt).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "client_json.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/sha256.h"
#include "loopback_postgres.h"
#include "metrics_scrape.h"
#include "server_process.h"

namespace isocorr::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kLease = "2";  // seconds: a dead replica's job is taken over soon

// The large pair's subdivision level: 2562 vertices run for seconds in Release; under the
// sanitizers 642 already run long enough, and the takeover tests wait for the whole job,
// some twice.
#ifdef ISOCORR_SANITIZED
constexpr int kLargeSubdivisions = 3;
#else
constexpr int kLargeSubdivisions = 4;
#endif

class Replicas : public LoopbackPostgresTest {
 protected:
  static void SetUpTestSuite() {
    LoopbackPostgresTest::SetUpTestSuite();
    if (!postgres_) return;
    dir_ = new fs::path(fs::temp_directory_path() / ("isocorr_replicas_test_" + std::to_string(getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const TriangleMesh creature = limbed_blob(3);
    write_ply((*dir_ / "creature.ply").string(), creature);
    write_ply((*dir_ / "creature_moved.ply").string(), rotated_scaled_renumbered(creature, 1.3, 7).mesh);
    // Larger: a job on it is still running when the test acts on it.
    const TriangleMesh large = limbed_blob(kLargeSubdivisions);
    write_ply((*dir_ / "large.ply").string(), large);
    write_ply((*dir_ / "large_moved.ply").string(), rotated_scaled_renumbered(large, 0.8, 11).mesh);
  }
  static void TearDownTestSuite() {
    LoopbackPostgresTest::TearDownTestSuite();
    if (dir_) fs::remove_all(*dir_);
    delete dir_;
    dir_ = nullptr;
  }
  void TearDown() override {
    replicas_[0].reset();
    replicas_[1].reset();
  }

  // Replica `i` ("replica-0" or "replica-1") on the shared store, started (again), with its
  // metrics on a free loopback port.
  ServerProcess& start_replica(int i) {
    replicas_[i].reset();
    const fs::path data_dir = *dir_ / (database_ + "_replica-" + std::to_string(i));
    replicas_[i] = std::make_unique<ServerProcess>(
        data_dir, std::vector<std::string>{"--store", database_url(), "--replica-id", replica_id(i),
                                           "--lease-seconds", kLease, "--threads", "1", "--metrics-listen",
                                           "127.0.0.1:0", "--metrics-port-file", data_dir.string() + ".mport"});
    metrics_ports_[i] = std::stoi(slurp_file(data_dir.string() + ".mport"));
    return *replicas_[i];
  }
  std::string scrape(int i) const {
    const auto [status, body] = http_get(metrics_ports_[i], "/metrics");
    EXPECT_EQ(status, 200) << body;
    return body;
  }
  static std::string replica_id(int i) { return "replica-" + std::to_string(i); }
  static fs::path path(const std::string& name) { return *dir_ / name; }

  // The database's view of a job: state and the replica holding it ("" when none).
  std::pair<std::string, std::string> claim_of(const std::string& job) const {
    const CommandRun row = sql("SELECT state || '|' || coalesce(claimed_by, '') FROM isocorr_jobs "
                                          "WHERE id = '" + job.substr(5) + "'");
    const std::string line = row.out.substr(0, row.out.find('\n'));
    const size_t bar = line.find('|');
    if (bar == std::string::npos) return {"", ""};
    return {line.substr(0, bar), line.substr(bar + 1)};
  }
  // Polls (bounded) until the database shows the job RUNNING under some replica.
  std::string wait_until_claimed(const std::string& job) const {
    for (int i = 0; i < 2400; ++i) {
      const auto [state, holder] = claim_of(job);
      if (state == "RUNNING" && !holder.empty()) return holder;
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
    ADD_FAILURE() << job << " was never claimed";
    return "";
  }
  // Both replicas started, and the large pair's job submitted through the first: the job
  // and the replica that claimed it ("" when the submit failed).
  std::pair<std::string, int> large_job_on_two_replicas() {
    ServerProcess& first = start_replica(0);
    start_replica(1);
    const CommandRun submit =
        first.client("submit " + path("large.ply").string() + " " + path("large_moved.ply").string() + " --json");
    EXPECT_EQ(submit.exit_code, 0) << submit.err;
    const std::string job = last_json(submit).value("name", "");
    if (job.empty()) return {"", 0};
    return {job, wait_until_claimed(job) == replica_id(0) ? 0 : 1};
  }
  static json wait_done(const ServerProcess& replica, const std::string& job) {
    return last_json(replica.client("wait " + job + " --timeout 600 --json"));
  }
  // The job's maps and report downloaded through `replica`, concatenated; empty on failure.
  std::string download(const ServerProcess& replica, const std::string& job, const std::string& tag) const {
    const fs::path map = path(database_ + tag + ".map"), reverse = path(database_ + tag + ".rmap"),
                   report = path(database_ + tag + ".json");
    const CommandRun run = replica.client("download " + job + " -o " + map.string() + " --reverse-out " +
                                          reverse.string() + " --report " + report.string());
    EXPECT_EQ(run.exit_code, 0) << run.err;
    if (run.exit_code != 0) return "";
    return slurp_file(map) + slurp_file(reverse) + slurp_file(report);
  }

  static fs::path* dir_;
  std::unique_ptr<ServerProcess> replicas_[2];
  int metrics_ports_[2] = {0, 0};
};
fs::path* Replicas::dir_ = nullptr;

TEST_F(Replicas, AnyReplicaServesAnyCallAndAKilledReplicasJobCompletesOnTheOther) {
  ServerProcess& first = start_replica(0);
  ServerProcess& second = start_replica(1);

  // Upload through one, see it through the other.
  const CommandRun upload = first.client("upload " + path("creature.ply").string() + " " +
                                         path("creature_moved.ply").string() + " " + path("large.ply").string() +
                                         " " + path("large_moved.ply").string() + " --json");
  ASSERT_EQ(upload.exit_code, 0) << upload.err;
  const auto mesh_name = [&](const std::string& file) { return "meshes/" + sha256_hex(slurp_file(path(file))); };
  const json seen = last_json(second.client("status " + mesh_name("creature.ply") + " --json"));
  EXPECT_EQ(seen.value("name", ""), mesh_name("creature.ply")) << seen.dump();
  const CommandRun listed = second.client("list meshes --json");
  for (const char* file : {"creature.ply", "creature_moved.ply", "large.ply", "large_moved.ply"})
    EXPECT_NE(listed.out.find(mesh_name(file)), std::string::npos) << file;

  // Match through the second, follow and download through either: the same bytes.
  const CommandRun submit =
      second.client("submit " + mesh_name("creature.ply") + " " + mesh_name("creature_moved.ply") + " --json");
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const std::string job = last_json(submit)["name"];
  const json done = wait_done(first, job);
  ASSERT_EQ(done.value("state", ""), "SUCCEEDED") << done.dump();

  // Metrics: both replicas count the job from the shared store; the one that ran it, and
  // only that one, recorded its duration.
  const std::string metrics[2] = {scrape(0), scrape(1)};
  double durations = 0;
  for (const std::string& text : metrics) {
    EXPECT_EQ(sample(text, "isocorr_jobs{state=\"SUCCEEDED\"}"), 1) << text;
    EXPECT_EQ(sample(text, "isocorr_job_queue_length"), 0) << text;
    // Absent (-1) on a replica that has ended no job yet.
    durations += std::max(0.0, sample(text, "isocorr_job_duration_seconds_count{state=\"SUCCEEDED\"}"));
  }
  EXPECT_EQ(durations, 1);
  const std::string through_first = download(first, job, "first"), through_second = download(second, job, "second");
  EXPECT_FALSE(through_first.empty());
  EXPECT_EQ(sha256_hex(through_first), sha256_hex(through_second));

  // kill -9 the replica running a job, mid-job: the other takes it over after the lease.
  const CommandRun long_submit =
      first.client("submit " + mesh_name("large.ply") + " " + mesh_name("large_moved.ply") + " --json");
  ASSERT_EQ(long_submit.exit_code, 0) << long_submit.err;
  const std::string long_job = last_json(long_submit)["name"];
  const std::string holder = wait_until_claimed(long_job);
  ASSERT_TRUE(holder == replica_id(0) || holder == replica_id(1)) << holder;
  const int victim = holder == replica_id(0) ? 0 : 1, survivor = 1 - victim;
  replicas_[victim]->kill_hard();
  // Still RUNNING under the dead replica: it was killed mid-job, not after the job ended.
  ASSERT_EQ(claim_of(long_job), std::make_pair(std::string("RUNNING"), replica_id(victim)));
  const json taken_over = wait_done(*replicas_[survivor], long_job);
  EXPECT_EQ(taken_over.value("state", ""), "SUCCEEDED") << taken_over.dump();
  EXPECT_EQ(taken_over.value("attempts", 0), 2) << taken_over.dump();
  std::printf("job %s: replica %s killed mid-job, finished by %s\n", long_job.c_str(), replica_id(victim).c_str(),
              replica_id(survivor).c_str());

  // Nothing lost: the restarted replica sees every mesh and job, and serves both results.
  ServerProcess& restarted = start_replica(victim);
  const CommandRun jobs = restarted.client("list --json");
  EXPECT_NE(jobs.out.find(job), std::string::npos);
  EXPECT_NE(jobs.out.find(long_job), std::string::npos);
  EXPECT_EQ(sha256_hex(download(restarted, job, "restarted")), sha256_hex(through_first));
  const std::string long_result = download(restarted, long_job, "long_restarted");
  EXPECT_FALSE(long_result.empty());
  EXPECT_EQ(sha256_hex(download(*replicas_[survivor], long_job, "long_survivor")), sha256_hex(long_result));
}

TEST_F(Replicas, AStoppingReplicaHandsItsRunningJobToAnotherAtOnce) {
  const auto [job, stopping] = large_job_on_two_replicas();
  ASSERT_FALSE(job.empty());
  const int other = 1 - stopping;
  EXPECT_EQ(replicas_[stopping]->terminate(), 0);
  const json done = wait_done(*replicas_[other], job);
  EXPECT_EQ(done.value("state", ""), "SUCCEEDED") << done.dump();
  // Queued again by the stopping replica, so its start was not counted as a crash, and
  // run to the end by the other one.
  EXPECT_EQ(done.value("attempts", 0), 1) << done.dump();
  // Its log line names the job and the call that created it on the stopping replica.
  const std::string log = slurp_file(replicas_[other]->log_path());
  const size_t line = log.find("[job " + job.substr(5) + " from r");
  ASSERT_NE(line, std::string::npos) << log;
  EXPECT_EQ(log.find("] running on replica " + replica_id(other), line), log.find(']', line)) << log;
}

TEST_F(Replicas, CancelReachesTheJobThroughAnyReplica) {
  const auto [job, holder] = large_job_on_two_replicas();
  ASSERT_FALSE(job.empty());
  // Cancelled through the replica that does not run it.
  const ServerProcess& other = *replicas_[1 - holder];
  const CommandRun cancel = other.client("cancel " + job + " --json");
  ASSERT_EQ(cancel.exit_code, 0) << cancel.err;
  EXPECT_EQ(wait_done(other, job).value("state", ""), "CANCELLED");
  EXPECT_EQ(claim_of(job).first, "CANCELLED");
}

TEST_F(Replicas, CorruptedBytesInTheDatabaseAreDataLossAndAnUploadRepairsThem) {
  ServerProcess& first = start_replica(0);
  ServerProcess& second = start_replica(1);
  const CommandRun submit = first.client("submit " + path("creature.ply").string() + " " +
                                         path("creature_moved.ply").string() + " --json");
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const json created = last_json(submit);
  const std::string job = created["name"], mesh = created["source_mesh"];
  ASSERT_EQ(wait_done(second, job).value("state", ""), "SUCCEEDED");

  // A changed byte of a stored mesh: DATA_LOSS through either replica until uploaded again.
  ASSERT_EQ(sql("UPDATE isocorr_meshes SET bytes = set_byte(bytes, 100, get_byte(bytes, 100) # 1) "
                           "WHERE digest = '" + mesh.substr(7) + "'").exit_code, 0);
  EXPECT_EQ(error_code(second.client("status " + mesh + " --json")), "DATA_LOSS");
  EXPECT_EQ(error_code(first.client("status " + mesh + " --json")), "DATA_LOSS");
  const CommandRun repair = first.client("upload " + path("creature.ply").string() + " --json");
  ASSERT_EQ(repair.exit_code, 0) << repair.err;
  EXPECT_TRUE(last_json(repair)["uploaded"].get<bool>());
  EXPECT_EQ(second.client("status " + mesh).exit_code, 0);

  // A changed byte of a stored result part: the download is DATA_LOSS and writes nothing.
  ASSERT_EQ(sql("UPDATE isocorr_result_parts SET bytes = set_byte(bytes, 0, get_byte(bytes, 0) # 1) "
                           "WHERE job_id = '" + job.substr(5) + "' AND part = 'forward'").exit_code, 0);
  const fs::path map = path("corrupted.map");
  const CommandRun download = second.client("download " + job + " -o " + map.string() + " --json");
  EXPECT_EQ(error_code(download), "DATA_LOSS") << download.out;
  EXPECT_FALSE(fs::exists(map));
}

}  // namespace
}  // namespace isocorr::testing

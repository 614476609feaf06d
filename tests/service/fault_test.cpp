// The service under faults, with the real server and client on loopback, in a bounded
// cycle: kill -9 during uploads and jobs (every acknowledged upload and job is there after
// the restart: the acknowledged bytes lost are printed and must be 0), a full disk (a
// file-size limit set on the running server with prlimit: writes fail with EFBIG, which the
// server treats like ENOSPC), a corrupted store (a changed byte in a stored mesh,
// result and job record: DATA_LOSS, quarantine, repair by uploading again), a job that
// stops its server twice (not run a third time) and a second server on the same data
// directory (refused).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/sha256.h"
#include "server_process.h"
#include "storage/sealed_json.h"

namespace isocorr::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> objects;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line[0] == '{') {
      json object = json::parse(line, nullptr, false);
      if (object.is_object()) objects.push_back(std::move(object));
    }
  return objects;
}

json last_json(const CommandRun& run) {
  const std::vector<json> objects = json_lines(run.out);
  return objects.empty() ? json::object() : objects.back();
}

std::string error_code(const CommandRun& run) { return last_json(run).value("error", json::object()).value("code", ""); }
std::string error_message(const CommandRun& run) {
  return last_json(run).value("error", json::object()).value("message", "");
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}


void flip_byte(const fs::path& path) {
  std::string bytes = slurp(path);
  bytes[bytes.size() / 2] ^= 0x01;
  std::ofstream(path, std::ios::binary) << bytes;
}

// Regular files the server writes from now on fail beyond `bytes` (it ignores SIGXFSZ).
void limit_file_size(const ServerProcess& server, rlim_t bytes) {
  rlimit limit{};
  ASSERT_EQ(prlimit(server.pid(), RLIMIT_FSIZE, nullptr, &limit), 0);
  limit.rlim_cur = std::min(bytes, limit.rlim_max);
  ASSERT_EQ(prlimit(server.pid(), RLIMIT_FSIZE, &limit, nullptr), 0);
}

// Files under `dir` that an unfinished write leaves behind.
std::vector<std::string> leftovers(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    const bool temporary = name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0;
    const bool in_tmp = entry.path().parent_path().filename() == "tmp";
    if (temporary || in_tmp) found.push_back(entry.path().string());
  }
  return found;
}

class Faults : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("isocorr_fault_test_" + std::to_string(getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const TriangleMesh creature = limbed_blob(3);
    write_ply((*dir_ / "creature.ply").string(), creature);
    write_ply((*dir_ / "creature_moved.ply").string(), rotated_scaled_renumbered(creature, 1.3, 7).mesh);
    // Distinct small meshes for the kill -9 rounds: each upload is a new object.
    const TriangleMesh small = limbed_blob(2);
    for (int i = 0; i < kSmallMeshes; ++i)
      write_ply(small_mesh(i).string(), rotated_scaled_renumbered(small, 1.0 + 0.01 * i, 100 + i).mesh);
    // Slow to preprocess: a job on it is still running when the test acts on it.
    std::ofstream sphere(*dir_ / "sphere.off");
    const TriangleMesh ball = icosphere(7);
    sphere << "OFF\n" << ball.num_vertices() << ' ' << ball.num_faces() << " 0\n";
    for (const Vec3& p : ball.vertices) sphere << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const Face& f : ball.faces) sphere << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path path(const std::string& name) { return *dir_ / name; }
  static fs::path small_mesh(int i) { return *dir_ / ("small_" + std::to_string(i) + ".ply"); }
  fs::path data_dir() const {
    return *dir_ / (std::string("data_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }

  // Polls (bounded) until `done` holds for the job's status.
  template <typename Predicate>
  static json wait_for_status(const ServerProcess& server, const std::string& job, Predicate done) {
    json status;
    for (int i = 0; i < 1200; ++i) {
      status = last_json(server.client("status " + job + " --json"));
      if (done(status)) return status;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ADD_FAILURE() << job << " never reached the expected state: " << status.dump();
    return status;
  }
  static json wait_done(const ServerProcess& server, const std::string& job) {
    const CommandRun wait = server.client("wait " + job + " --json");
    return last_json(wait);
  }

  static constexpr int kSmallMeshes = 18;
  static fs::path* dir_;
};
fs::path* Faults::dir_ = nullptr;

TEST_F(Faults, KillNineLosesNoAcknowledgedUploadOrJob) {
  constexpr int kRounds = 3, kPerRound = kSmallMeshes / kRounds;
  std::map<std::string, int64_t> acknowledged_meshes;  // name -> size_bytes
  std::set<std::string> acknowledged_jobs;
  for (int round = 0; round <= kRounds; ++round) {
    ServerProcess server(data_dir());
    // Everything acknowledged so far is still there after the kill -9 and the restart.
    int64_t bytes_lost = 0;
    int jobs_lost = 0;
    std::set<std::string> meshes, jobs;
    for (const json& mesh : json_lines(server.client("list meshes --json").out)) meshes.insert(mesh.value("name", ""));
    for (const json& job : json_lines(server.client("list --json").out)) jobs.insert(job.value("name", ""));
    for (const auto& [name, size] : acknowledged_meshes)
      if (!meshes.count(name)) bytes_lost += size;
    for (const auto& name : acknowledged_jobs) jobs_lost += jobs.count(name) ? 0 : 1;
    std::printf("after kill -9 round %d: %zu uploads and %zu jobs acknowledged, acknowledged bytes lost: %lld, "
                "jobs lost: %d\n",
                round, acknowledged_meshes.size(), acknowledged_jobs.size(), static_cast<long long>(bytes_lost),
                jobs_lost);
    EXPECT_EQ(bytes_lost, 0);
    EXPECT_EQ(jobs_lost, 0);
    EXPECT_TRUE(leftovers(data_dir()).empty()) << leftovers(data_dir())[0];  // cleaned at start
    if (round == kRounds) break;

    // Uploads and jobs in a background client, killed under it once the first is acknowledged.
    const fs::path script = data_dir().string() + "_round.sh", log = data_dir().string() + "_round.log";
    std::ofstream out(script);
    const std::string client = std::string(ISOCORR_CLI_PATH) + " --server " + server.address();
    for (int i = round * kPerRound; i < (round + 1) * kPerRound; ++i) {
      out << client << " upload " << small_mesh(i).string() << " --json\n";
      out << client << " submit " << small_mesh(i).string() << ' ' << path("creature.ply").string() << " --json\n";
    }
    out.close();
    fs::remove(log);
    const pid_t pid = spawn_command("sh " + script.string(), log);
    // Killed after 2, 5 and 8 acknowledgements: with an upload or a job under way (or the
    // script ended). Each round starts by uploading, so the cycle is never empty.
    const size_t acknowledgements = 2 + 3 * static_cast<size_t>(round);
    for (int i = 0; i < 1500 && json_lines(slurp(log)).size() < acknowledgements && waitpid(pid, nullptr, WNOHANG) == 0;
         ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    server.kill_hard();
    if (waitpid(pid, nullptr, WNOHANG) == 0) wait_for_exit(pid);
    for (const json& line : json_lines(slurp(log))) {
      if (line.contains("mesh")) acknowledged_meshes[line["mesh"]["name"]] = std::stoll(line["mesh"]["size_bytes"].get<std::string>());
      if (line.value("name", "").rfind("jobs/", 0) == 0) acknowledged_jobs.insert(line["name"]);
    }
  }
  EXPECT_GE(acknowledged_meshes.size(), static_cast<size_t>(kRounds));
  EXPECT_GE(acknowledged_jobs.size(), static_cast<size_t>(kRounds));
}

TEST_F(Faults, FullDiskIsResourceExhaustedAndNoJobStaysStuck) {
  ServerProcess server(data_dir(), {"--threads", "1"});
  const std::string creature = path("creature.ply").string(), moved = path("creature_moved.ply").string();
  const std::string sphere = path("sphere.off").string();
  ASSERT_EQ(server.client("upload " + creature + " " + moved).exit_code, 0);
  const std::string data = fs::canonical(data_dir()).string();

  // 8 KiB: a job record fits, a mesh or a result's report does not.
  limit_file_size(server, 8192);
  const CommandRun upload = server.client("upload " + sphere + " --json");
  EXPECT_EQ(error_code(upload), "RESOURCE_EXHAUSTED") << upload.out << upload.err;
  EXPECT_EQ(error_message(upload).find(data), std::string::npos) << error_message(upload);
  EXPECT_TRUE(leftovers(data_dir()).empty()) << leftovers(data_dir())[0];
  EXPECT_EQ(std::distance(fs::directory_iterator(data_dir() / "meshes"), fs::directory_iterator()), 4);
  const CommandRun submit = server.client("submit " + creature + " " + moved + " --json");
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const json no_room_for_result = wait_done(server, last_json(submit)["name"]);
  EXPECT_EQ(no_room_for_result["state"], "FAILED") << no_room_for_result.dump();
  EXPECT_EQ(no_room_for_result["error"]["code"], 8) << no_room_for_result.dump();  // RESOURCE_EXHAUSTED
  EXPECT_NE(no_room_for_result["error"]["message"].get<std::string>().find("disk is full"), std::string::npos);
  EXPECT_TRUE(leftovers(data_dir()).empty()) << leftovers(data_dir())[0];

  // Nothing fits: CreateMatchJob is refused; a job whose end cannot be recorded is not
  // shown done (a restart would run it again) but waits for room, and the queue with it.
  limit_file_size(server, 0);
  const CommandRun refused = server.client("submit " + creature + " " + moved + " --json");
  EXPECT_EQ(error_code(refused), "RESOURCE_EXHAUSTED") << refused.out;
  EXPECT_EQ(error_message(refused).find(data), std::string::npos) << error_message(refused);
  limit_file_size(server, RLIM_INFINITY);
  const std::string long_job = last_json(server.client("submit " + sphere + " " + sphere + " --json"))["name"];
  wait_for_status(server, long_job, [](const json& s) { return s.value("state", "") == "RUNNING"; });
  const std::string queued = last_json(server.client("submit " + creature + " " + moved + " --json"))["name"];
  limit_file_size(server, 0);
  ASSERT_EQ(server.client("cancel " + long_job).exit_code, 0);
  wait_for_status(server, long_job, [](const json& s) {
    return s.value("state", "") == "RUNNING" &&
           s["progress"].value("stage", "") == "waiting for disk space to record its end";
  });
  EXPECT_EQ(last_json(server.client("status " + queued + " --json")).value("state", ""), "QUEUED");

  // Room again: the cancel is recorded, the waiting job runs, uploads work, and no job is
  // left unfinished.
  limit_file_size(server, RLIM_INFINITY);
  EXPECT_EQ(wait_done(server, long_job)["state"], "CANCELLED");
  EXPECT_EQ(wait_done(server, queued)["state"], "SUCCEEDED");
  EXPECT_TRUE(last_json(server.client("upload " + small_mesh(0).string() + " --json"))["uploaded"].get<bool>());
  const fs::path map = data_dir().string() + ".map";
  EXPECT_EQ(server.client("download " + queued + " -o " + map.string()).exit_code, 0);
  for (const json& job : json_lines(server.client("list --json").out)) EXPECT_TRUE(job.value("done", false)) << job.dump();
}

TEST_F(Faults, CorruptedStoreIsDataLossQuarantinedAndRepairedByUpload) {
  const std::string creature = path("creature.ply").string(), moved = path("creature_moved.ply").string();
  std::string job, mesh, target;
  {
    ServerProcess server(data_dir());
    const CommandRun submit = server.client("submit " + creature + " " + moved + " --json");
    ASSERT_EQ(submit.exit_code, 0) << submit.err;
    job = last_json(submit)["name"];
    mesh = last_json(submit)["source_mesh"];
    target = last_json(submit)["target_mesh"];
    ASSERT_EQ(wait_done(server, job)["state"], "SUCCEEDED");
    const std::string digest = mesh.substr(7), id = job.substr(5);

    // A stored mesh: DATA_LOSS (for jobs too), set aside, repaired by uploading it again.
    flip_byte(data_dir() / "meshes" / (digest + ".mesh"));
    EXPECT_EQ(error_code(server.client("status " + mesh + " --json")), "DATA_LOSS");
    EXPECT_TRUE(fs::exists(data_dir() / "quarantine" / "meshes" / (digest + ".mesh")));
    EXPECT_EQ(error_code(server.client("submit " + mesh + " " + moved + " --json")), "DATA_LOSS");
    const CommandRun repair = server.client("upload " + creature + " --json");
    ASSERT_EQ(repair.exit_code, 0) << repair.err;
    EXPECT_TRUE(last_json(repair)["uploaded"].get<bool>());
    EXPECT_EQ(server.client("status " + mesh).exit_code, 0);

    // A stored result: the download fails with DATA_LOSS and writes nothing.
    const fs::path forward = data_dir() / "results" / id / "forward.i32";
    std::string bytes = slurp(forward);
    bytes.replace(0, 4, std::string("\xff\xff\xff\x7f", 4));  // 2147483647
    std::ofstream(forward, std::ios::binary) << bytes;
    const fs::path map = data_dir().string() + ".map";
    const CommandRun download = server.client("download " + job + " -o " + map.string() + " --json");
    EXPECT_NE(download.exit_code, 0);
    EXPECT_EQ(error_code(download), "DATA_LOSS") << download.out;
    EXPECT_FALSE(fs::exists(map));
    EXPECT_TRUE(fs::exists(data_dir() / "quarantine" / "results" / id));
    EXPECT_EQ(error_code(server.client("download " + job + " -o " + map.string() + " --json")), "DATA_LOSS");
    EXPECT_EQ(server.terminate(), 0);
  }
  // A job record, read at start: the job is kept and reported FAILED with DATA_LOSS.
  const std::string id = job.substr(5);
  flip_byte(data_dir() / "jobs" / (id + ".json"));
  ServerProcess restarted(data_dir());
  const json status = last_json(restarted.client("status " + job + " --json"));
  EXPECT_EQ(status["state"], "FAILED") << status.dump();
  EXPECT_EQ(status["error"]["code"], 15) << status.dump();  // DATA_LOSS
  EXPECT_TRUE(fs::exists(data_dir() / "quarantine" / "jobs" / (id + ".json")));
  EXPECT_NE(restarted.client("list --json").out.find(job), std::string::npos);

  // A mesh corrupted where only its bytes show it (same size): the job reading it fails
  // with DATA_LOSS rather than matching other bytes; uploading it again repairs it.
  flip_byte(data_dir() / "meshes" / (target.substr(7) + ".mesh"));
  const CommandRun on_corrupted = restarted.client("submit " + mesh + " " + target + " --json");
  ASSERT_EQ(on_corrupted.exit_code, 0) << on_corrupted.err;
  const json lost = wait_done(restarted, last_json(on_corrupted)["name"]);
  EXPECT_EQ(lost["state"], "FAILED") << lost.dump();
  EXPECT_EQ(lost["error"]["code"], 15) << lost.dump();
  EXPECT_TRUE(last_json(restarted.client("upload " + moved + " --json"))["uploaded"].get<bool>());
  const CommandRun again = restarted.client("submit " + mesh + " " + target + " --json");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const std::string repaired_job = last_json(again)["name"];
  EXPECT_EQ(wait_done(restarted, repaired_job)["state"], "SUCCEEDED");

  // A result whose manifest was rewritten to match a bad index fools the server's checks,
  // not the client's: it refuses an index outside the target's vertices and writes nothing.
  const fs::path result = data_dir() / "results" / repaired_job.substr(5);
  std::string forward = slurp(result / "forward.i32");
  const int32_t outside = 1000000;
  std::memcpy(forward.data(), &outside, sizeof outside);
  std::ofstream(result / "forward.i32", std::ios::binary) << forward;
  json manifest = server::unseal_json(slurp(result / "manifest.json"));
  manifest["target_vertices"] = 2 * outside;
  manifest["parts"]["forward"]["sha256"] = sha256_hex(forward);
  std::ofstream(result / "manifest.json", std::ios::binary) << server::seal_json(manifest);
  const fs::path map = data_dir().string() + "_forged.map";
  const CommandRun forged = restarted.client("download " + repaired_job + " -o " + map.string() + " --json");
  EXPECT_EQ(forged.exit_code, 1);
  EXPECT_EQ(error_code(forged), "DATA_LOSS") << forged.out;
  EXPECT_NE(error_message(forged).find("outside"), std::string::npos) << error_message(forged);
  EXPECT_FALSE(fs::exists(map));
}

TEST_F(Faults, AJobThatStoppedItsServerTwiceFailsInsteadOfRunningAThirdTime) {
  std::string job;
  for (int stop = 1; stop <= 2; ++stop) {
    ServerProcess server(data_dir(), {"--threads", "1"});
    if (job.empty()) job = last_json(server.client("submit " + path("sphere.off").string() + " " +
                                                   path("sphere.off").string() + " --json"))["name"];
    wait_for_status(server, job, [&](const json& s) {
      return s.value("state", "") == "RUNNING" && s.value("attempts", 0) == stop;
    });
    server.kill_hard();  // as if the job had brought it down
  }
  ServerProcess server(data_dir(), {"--threads", "1"});
  const json status = last_json(server.client("status " + job + " --json"));
  EXPECT_EQ(status.value("state", ""), "FAILED") << status.dump();
  EXPECT_NE(status.dump().find("stopped the server twice"), std::string::npos) << status.dump();
}

TEST_F(Faults, ASecondServerOnTheSameDataDirectoryRefusesToStartNamingTheFirst) {
  ServerProcess first(data_dir());
  std::string refusal;
  try {
    ServerProcess second(data_dir());
  } catch (const std::runtime_error& e) {
    refusal = e.what();
  }
  EXPECT_NE(refusal.find("in use by another isocorr-server (pid " + std::to_string(first.pid()) + ")"),
            std::string::npos)
      << refusal;
  first.kill_hard();  // the kernel releases the lock with its holder
  ServerProcess after_crash(data_dir());
  EXPECT_TRUE(after_crash.running());
}

}  // namespace
}  // namespace isocorr::testing

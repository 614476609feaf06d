// isocorr-server driven by the isocorr client, both the real binaries, on loopback:
// uploads (one above gRPC's 4 MiB message limit), duplicates, match, watch, cancel,
// download, kill -9 and recovery, auth, and the status codes of the API.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/procedural_meshes.h"
#include "client_json.h"
#include "server_process.h"
#include "suite_files.h"

namespace isocorr::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// "2026-11-23T11:22:33.456Z" (proto3 JSON timestamp) -> milliseconds since midnight.
int64_t milliseconds_of_day(const std::string& timestamp) {
  const size_t t = timestamp.find('T');
  const int hours = std::stoi(timestamp.substr(t + 1, 2)), minutes = std::stoi(timestamp.substr(t + 4, 2));
  const double seconds = std::stod(timestamp.substr(t + 7, timestamp.size() - t - 8));
  return (hours * 60 + minutes) * 60000 + static_cast<int64_t>(seconds * 1000);
}

// End minus start of two such timestamps taken less than a day apart.
int64_t elapsed_ms(const std::string& start, const std::string& end) {
  const int64_t ms = milliseconds_of_day(end) - milliseconds_of_day(start);
  return ms < 0 ? ms + 24 * 3600 * 1000 : ms;
}

std::vector<int> read_ints(const fs::path& path) {
  std::vector<int> values;
  std::ifstream in(path);
  for (int v; in >> v;) values.push_back(v);
  return values;
}

void write_ascii_off(const fs::path& path, const TriangleMesh& mesh) {
  std::ofstream out(path);
  out << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
  out.precision(17);
  for (const Vec3& p : mesh.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const Face& f : mesh.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

class Service : public WithSuiteFiles<Service> {
 protected:
  static void SetUpTestSuite() {
    make_suite_dir("isocorr_service_test");
    // A small asymmetric pair with a known answer: matches in seconds.
    const TriangleMesh creature = limbed_blob(3);
    const RenumberedCopy moved = rotated_scaled_renumbered(creature, 1.3, 7);
    write_ply(path("creature.ply").string(), creature);
    write_ply(path("creature_moved.ply").string(), moved.mesh);
    *truth_ = moved.permutation;
    // Above gRPC's 4 MiB default message size, so it must travel in chunks; and slow to
    // preprocess, so jobs on it are still running when the tests cancel or kill them.
    write_ascii_off(path("sphere.off"), icosphere(7));
    std::ofstream(path("broken.off")) << "OFF\n3 1 0\n0 0 0\n1 0 0\n";
    std::ofstream(path("tetrahedron.off"))
        << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
    std::ofstream(path("token")) << "s3cret-token\n";
    std::ofstream(path("wrong_token")) << "guess\n";
  }

  // Polls (bounded) until the job is RUNNING; the job must not finish meanwhile.
  static void wait_until_running(const ServerProcess& server, const std::string& job) {
    for (int i = 0; i < 600; ++i) {
      const json status = last_json(server.client("status " + job + " --json"));
      if (status.value("state", "") == "RUNNING") return;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    FAIL() << job << " never started";
  }

  static std::vector<int>* truth_;
};
std::vector<int>* Service::truth_ = new std::vector<int>;

TEST_F(Service, UploadsLargeMeshInChunksAndDuplicateIsNoOp) {
  ASSERT_GT(fs::file_size(path("sphere.off")), 4u << 20);
  ServerProcess server(data_dir());
  const CommandRun first = server.client("upload " + path("sphere.off").string() + " --json");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const json uploaded = last_json(first);
  EXPECT_TRUE(uploaded["uploaded"].get<bool>());
  EXPECT_EQ(uploaded["mesh"]["vertex_count"], 163842);
  EXPECT_EQ(uploaded["mesh"]["size_bytes"], std::to_string(fs::file_size(path("sphere.off"))));  // int64 is a JSON string
  const std::string name = uploaded["mesh"]["name"];

  const CommandRun again = server.client("upload " + path("sphere.off").string() + " --json");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_FALSE(last_json(again)["uploaded"].get<bool>());
  EXPECT_EQ(last_json(again)["mesh"]["name"], name);

  const CommandRun listed = server.client("list meshes --json");
  ASSERT_EQ(listed.exit_code, 0);
  EXPECT_EQ(last_json(listed)["name"], name);
  const CommandRun status = server.client("status " + name + " --json");
  EXPECT_EQ(last_json(status)["preprocessing_state"], "NOT_PREPROCESSED");
}

TEST_F(Service, RemoteMatchWritesMapsReportAndColouredMeshes) {
  ServerProcess server(data_dir());
  const fs::path map = data_dir() / "out.map", reverse = data_dir() / "out.rmap", report = data_dir() / "report.json";
  // --server after the subcommand here (ServerProcess::client puts it before).
  const CommandRun match = run_command(std::string(ISOCORR_CLI_PATH) + " match " + path("creature.ply").string() + " " +
                                       path("creature_moved.ply").string() + " -o " + map.string() + " --reverse-out " +
                                       reverse.string() + " --report " + report.string() + " --colour-ply " +
                                       (data_dir() / "view_").string() + " --server " + server.address());
  ASSERT_EQ(match.exit_code, 0) << match.err;
  const std::vector<int> forward = read_ints(map);
  ASSERT_EQ(forward.size(), truth_->size());
  EXPECT_EQ(read_ints(reverse).size(), truth_->size());
  int exact = 0;
  for (size_t i = 0; i < forward.size(); ++i) exact += forward[i] == (*truth_)[i];
  EXPECT_GE(exact, 0.9 * forward.size());
  std::ifstream in(report);
  EXPECT_EQ(json::parse(in)["verdict"]["status"], "ok");
  EXPECT_NE(match.err.find("verdict: ok"), std::string::npos) << match.err;  // the last line, as locally
  EXPECT_EQ(parse_mesh(std::string(std::istreambuf_iterator<char>(std::ifstream(data_dir() / "view_target.ply").rdbuf()), {}),
                       "view_target.ply").mesh.num_vertices(),
            static_cast<int>(truth_->size()));

  // The second match finds both meshes on the server and their preprocessing in the cache.
  const CommandRun again = server.client("match " + path("creature.ply").string() + " " +
                                         path("creature_moved.ply").string() + " -o " + map.string());
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("already on the server"), std::string::npos) << again.err;
  const CommandRun meshes = server.client("list meshes --json");
  EXPECT_NE(meshes.out.find("PREPROCESSED"), std::string::npos) << meshes.out;
}

TEST_F(Service, SubmitWatchWaitDownload) {
  ServerProcess server(data_dir());
  const CommandRun submit =
      server.client("submit " + path("creature.ply").string() + " " + path("creature_moved.ply").string() + " --json");
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const json created = last_json(submit);
  const std::string job = created["name"];
  EXPECT_FALSE(created["done"].get<bool>());

  const CommandRun watch = server.client("watch " + job + " --json");
  ASSERT_EQ(watch.exit_code, 0) << watch.err;
  const json final_state = last_json(watch);
  EXPECT_TRUE(final_state["done"].get<bool>());
  EXPECT_EQ(final_state["state"], "SUCCEEDED");
  EXPECT_EQ(final_state["result"]["source_vertex_count"].get<int>(), static_cast<int>(truth_->size()));
  EXPECT_EQ(final_state["result"]["verdict"], "ok");  // an exact copy: a clear choice
  EXPECT_NE(watch.out.find("\"stage\":\"tracking\""), std::string::npos);  // progress was pushed

  const CommandRun wait = server.client("wait " + job + " --json");
  EXPECT_EQ(wait.exit_code, 0);
  EXPECT_EQ(last_json(wait)["state"], "SUCCEEDED");

  const fs::path map = data_dir() / "d.map", confidence = data_dir() / "d.conf", report = data_dir() / "d.json";
  const fs::path precise = data_dir() / "d.precise";
  const CommandRun download = server.client("download " + job + " -o " + map.string() + " --confidence-out " +
                                            confidence.string() + " --report " + report.string() + " --precise-out " +
                                            precise.string());
  ASSERT_EQ(download.exit_code, 0) << download.err;
  // The precise map the server stored is the one the engine gives in-process.
  const fs::path local_map = data_dir() / "local.map", local_precise = data_dir() / "local.precise";
  const CommandRun local = run_command(std::string(ISOCORR_CLI_PATH) + " match " + path("creature.ply").string() + " " +
                                       path("creature_moved.ply").string() + " -o " + local_map.string() +
                                       " --precise-out " + local_precise.string());
  ASSERT_EQ(local.exit_code, 0) << local.err;
  auto bytes_of = [](const fs::path& file) {
    return std::string(std::istreambuf_iterator<char>(std::ifstream(file).rdbuf()), {});
  };
  const std::string downloaded = bytes_of(precise);
  EXPECT_EQ(downloaded, bytes_of(local_precise));
  EXPECT_EQ(std::count(downloaded.begin(), downloaded.end(), '\n'), static_cast<long>(truth_->size()));
  // The downloaded precise map carries the target's vertex numbers (as labels) onto the
  // source: the pair is an exact copy, so each source vertex gets its true partner.
  const fs::path target_numbers = data_dir() / "target_numbers.txt", pulled = data_dir() / "pulled.txt";
  {
    std::ofstream out(target_numbers);
    for (size_t t = 0; t < truth_->size(); ++t) out << t << '\n';
  }
  const CommandRun transfer =
      run_command(std::string(ISOCORR_CLI_PATH) + " transfer " + path("creature.ply").string() + " " +
                  path("creature_moved.ply").string() + " " + precise.string() + " --precise --labels --attribute " +
                  target_numbers.string() + " -o " + pulled.string());
  ASSERT_EQ(transfer.exit_code, 0) << transfer.err;
  EXPECT_EQ(read_ints(pulled), *truth_);
  EXPECT_EQ(read_ints(map).size(), truth_->size());
  std::ifstream conf(confidence);
  size_t lines = 0;
  for (std::string line; std::getline(conf, line);) ++lines;
  EXPECT_EQ(lines, truth_->size());
  EXPECT_TRUE(fs::file_size(report) > 0);

  const CommandRun list = server.client("list --json");
  EXPECT_EQ(last_json(list)["name"], job);
}

TEST_F(Service, PartMatchKeepsItsUnmatchedTargetVerticesThroughStoreAndRestart) {
  const fs::path part = data_dir() / "part.ply", index_map = data_dir() / "part_index.txt";
  fs::create_directories(data_dir());
  const CommandRun cut = run_command(std::string(ISOCORR_CLI_PATH) + " cut " + path("creature.ply").string() + " -o " +
                                     part.string() + " --index-map " + index_map.string() + " --keep 0.9 --seed 3");
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  std::string job;
  {
    ServerProcess server(data_dir());
    const CommandRun submit =
        server.client("submit " + part.string() + " " + path("creature_moved.ply").string() + " --partial --json");
    ASSERT_EQ(submit.exit_code, 0) << submit.err;
    job = last_json(submit)["name"];
    const CommandRun wait = server.client("wait " + job + " --json");
    ASSERT_EQ(last_json(wait)["state"], "SUCCEEDED") << wait.out << wait.err;
  }
  // After a restart the stored reverse map, -1 entries included, passes the integrity check.
  ServerProcess server(data_dir());
  const fs::path reverse = data_dir() / "part.rmap", report = data_dir() / "part.json";
  const CommandRun download = server.client("download " + job + " -o " + (data_dir() / "part.map").string() +
                                            " --reverse-out " + reverse.string() + " --report " + report.string());
  ASSERT_EQ(download.exit_code, 0) << download.err;
  const std::vector<int> back = read_ints(reverse);
  ASSERT_EQ(back.size(), truth_->size());
  const long unmatched = std::count(back.begin(), back.end(), -1);
  EXPECT_GT(unmatched, 0.02 * back.size());
  EXPECT_LT(unmatched, 0.3 * back.size());
  std::ifstream in(report);
  EXPECT_EQ(json::parse(in)["settings"]["method"], "part");
}

TEST_F(Service, CancelEndsJobCancelled) {
  ServerProcess server(data_dir());
  const std::string sphere = path("sphere.off").string();
  const CommandRun submit = server.client("submit " + sphere + " " + sphere + " --json");
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const std::string job = last_json(submit)["name"];
  wait_until_running(server, job);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  ASSERT_EQ(server.client("cancel " + job).exit_code, 0);
  const CommandRun wait = server.client("wait " + job + " --json");
  EXPECT_EQ(wait.exit_code, 4);
  EXPECT_EQ(last_json(wait)["state"], "CANCELLED");
  EXPECT_EQ(last_json(wait)["error"]["code"], 1);  // google.rpc.Code CANCELLED
  // The end time is when the job ended, not when it started.
  EXPECT_GE(elapsed_ms(last_json(wait)["start_time"], last_json(wait)["end_time"]), 400);

  const CommandRun again = server.client("cancel " + job + " --json");
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_EQ(error_code(again), "FAILED_PRECONDITION");
  const CommandRun download = server.client("download " + job + " -o x.map --json");
  EXPECT_EQ(error_code(download), "FAILED_PRECONDITION");
}

TEST_F(Service, ErrorsHaveTheirStatusCodes) {
  ServerProcess server(data_dir(), {"--max-queued-jobs", "1"});
  const CommandRun unknown_job = server.client("status jobs/0123456789abcdef --json");
  EXPECT_EQ(unknown_job.exit_code, 2);
  EXPECT_EQ(error_code(unknown_job), "NOT_FOUND");

  const CommandRun unknown_mesh =
      server.client("submit meshes/" + std::string(64, 'a') + " meshes/" + std::string(64, 'b') + " --json");
  EXPECT_EQ(error_code(unknown_mesh), "NOT_FOUND");

  const CommandRun broken = server.client("upload " + path("broken.off").string() + " --json");
  EXPECT_EQ(broken.exit_code, 2);
  EXPECT_EQ(error_code(broken), "INVALID_ARGUMENT");
  EXPECT_NE(last_json(broken)["error"]["message"].get<std::string>().find("not a usable mesh"), std::string::npos);

  const CommandRun bad_name = server.client("status meshes/xyz --json");
  EXPECT_EQ(error_code(bad_name), "INVALID_ARGUMENT");

  const CommandRun bad_setting = server.client("submit " + path("creature.ply").string() + " " +
                                               path("creature.ply").string() + " --level0-samples 2 --json");
  EXPECT_EQ(error_code(bad_setting), "INVALID_ARGUMENT");
  // A preprocessing setting out of range is refused at once, naming the field, not
  // accepted as a job that fails later.
  const CommandRun bad_radius = server.client("submit " + path("creature.ply").string() + " " +
                                              path("creature.ply").string() + " --level0-radius 5 --json");
  EXPECT_EQ(error_code(bad_radius), "INVALID_ARGUMENT");
  EXPECT_NE(last_json(bad_radius)["error"]["message"].get<std::string>().find("level0_radius"), std::string::npos);

  // A mesh that parses but cannot be matched (a tetrahedron: too few vertices) is refused
  // at upload, not accepted and failed by every job that uses it.
  const CommandRun tiny = server.client("upload " + path("tetrahedron.off").string() + " --json");
  EXPECT_EQ(tiny.exit_code, 2);
  EXPECT_EQ(error_code(tiny), "INVALID_ARGUMENT");
  EXPECT_NE(last_json(tiny)["error"]["message"].get<std::string>().find("at least 16"), std::string::npos);

  // One queued job at most: of three submissions, the second or third finds the queue full.
  const std::string sphere = path("sphere.off").string();
  std::vector<std::string> jobs;
  int exhausted = 0;
  for (int i = 0; i < 3; ++i) {
    const CommandRun submit = server.client("submit " + sphere + " " + sphere + " --json");
    if (submit.exit_code == 0) jobs.push_back(last_json(submit)["name"]);
    exhausted += error_code(submit) == "RESOURCE_EXHAUSTED";
  }
  EXPECT_GE(exhausted, 1);
  for (const auto& job : jobs) server.client("cancel " + job);

  const CommandRun in_use_or_gone = server.client("delete meshes/" + std::string(64, 'c') + " --json");
  EXPECT_EQ(error_code(in_use_or_gone), "NOT_FOUND");

  ServerProcess small(data_dir() / "small", {"--max-mesh-bytes", "1000"});
  const CommandRun too_big = small.client("upload " + sphere + " --json");
  EXPECT_EQ(error_code(too_big), "RESOURCE_EXHAUSTED");

  const int port = std::stoi(server.address().substr(server.address().rfind(':') + 1));
  server.kill_hard();
  const CommandRun unavailable =
      run_command(std::string(ISOCORR_CLI_PATH) + " health --server 127.0.0.1:" + std::to_string(port));
  EXPECT_EQ(unavailable.exit_code, 3);
}

// Every refusal of a mesh file names it, and whether it is the source or the target.
TEST_F(Service, MeshFileRefusalsNameTheFileAndItsRole) {
  ServerProcess server(data_dir());
  const std::string empty = (data_dir() / "empty.off").string(), missing = (data_dir() / "missing.off").string();
  std::ofstream{empty};
  const std::string creature = path("creature.ply").string(), broken = path("broken.off").string();

  const CommandRun upload = server.client("upload " + empty + " --json");
  EXPECT_EQ(upload.exit_code, 2);
  EXPECT_NE(upload.err.find("mesh file '" + empty + "': the mesh file is empty"), std::string::npos) << upload.err;
  EXPECT_EQ(upload.err.find("size_bytes"), std::string::npos) << upload.err;

  const std::vector<std::pair<std::string, std::string>> refusals = {
      {"submit " + empty + " " + creature, "source mesh '" + empty + "': the mesh file is empty"},
      {"submit " + creature + " " + missing, "target mesh '" + missing + "': neither a mesh file nor a mesh name"},
      {"submit " + creature + " " + broken, "cannot upload target mesh '" + broken + "': not a usable mesh"},
      {"match " + broken + " " + creature + " -o " + (data_dir() / "x.map").string(),
       "cannot upload source mesh '" + broken + "': not a usable mesh"},
      {"match " + creature + " " + empty + " -o " + (data_dir() / "x.map").string(),
       "target mesh '" + empty + "': the mesh file is empty"},
  };
  for (const auto& [arguments, expected] : refusals) {
    const CommandRun run = server.client(arguments);
    EXPECT_EQ(run.exit_code, 2) << arguments << "\n" << run.err;
    EXPECT_NE(run.err.find(expected), std::string::npos) << arguments << "\n" << run.err;
  }
  EXPECT_FALSE(fs::exists(data_dir() / "x.map"));

  const CommandRun negative = server.client("wait jobs/0123456789abcdef --wait-seconds -1");
  EXPECT_EQ(negative.exit_code, 2) << negative.err;
  EXPECT_NE(negative.err.find("--wait-seconds: must not be negative"), std::string::npos) << negative.err;
}

TEST_F(Service, TokenRequiredForEverythingButHealth) {
  ServerProcess server(data_dir(), {"--token-file", path("token").string()});
  EXPECT_EQ(server.client("health").exit_code, 0);
  const CommandRun anonymous = server.client("list --json");
  EXPECT_EQ(anonymous.exit_code, 5);
  EXPECT_EQ(error_code(anonymous), "UNAUTHENTICATED");
  const CommandRun wrong = server.client("--token-file " + path("wrong_token").string() + " list --json");
  EXPECT_EQ(error_code(wrong), "UNAUTHENTICATED");
  const CommandRun upload = server.client("upload " + path("creature.ply").string() + " --json");
  EXPECT_EQ(error_code(upload), "UNAUTHENTICATED");
  const CommandRun right = server.client("list --token-file " + path("token").string());
  EXPECT_EQ(right.exit_code, 0) << right.err;

  ServerProcess open(data_dir() / "open");
  EXPECT_EQ(open.client("list").exit_code, 0);
}

TEST_F(Service, KillNineKeepsMeshesAndResultsAndRequeuesTheRunningJob) {
  std::string finished, interrupted;
  {
    ServerProcess server(data_dir());
    const CommandRun done = server.client("submit " + path("creature.ply").string() + " " +
                                          path("creature_moved.ply").string() + " --json");
    ASSERT_EQ(done.exit_code, 0) << done.err;
    finished = last_json(done)["name"];
    ASSERT_EQ(server.client("wait " + finished).exit_code, 0);
    const std::string sphere = path("sphere.off").string();
    const CommandRun running = server.client("submit " + sphere + " " + sphere + " --json");
    ASSERT_EQ(running.exit_code, 0) << running.err;
    interrupted = last_json(running)["name"];
    wait_until_running(server, interrupted);
    server.kill_hard();
  }
  ServerProcess restarted(data_dir());
  const CommandRun meshes = restarted.client("list meshes --json");
  EXPECT_EQ(std::count(meshes.out.begin(), meshes.out.end(), '\n'), 3) << meshes.out;

  const CommandRun old = restarted.client("status " + finished + " --json");
  EXPECT_EQ(last_json(old)["state"], "SUCCEEDED");
  const fs::path map = data_dir() / "after_restart.map";
  ASSERT_EQ(restarted.client("download " + finished + " -o " + map.string()).exit_code, 0);
  EXPECT_EQ(read_ints(map).size(), truth_->size());

  const json again = last_json(restarted.client("status " + interrupted + " --json"));
  EXPECT_TRUE(again["state"] == "QUEUED" || again["state"] == "RUNNING") << again.dump();
  EXPECT_EQ(again["attempts"].get<int>() >= 1, true);
  // SIGTERM while it runs: a clean exit, and the job is queued again without losing an attempt.
  wait_until_running(restarted, interrupted);
  const int attempts = last_json(restarted.client("status " + interrupted + " --json"))["attempts"];
  EXPECT_EQ(attempts, 2);
  EXPECT_EQ(restarted.terminate(), 0);

  ServerProcess third(data_dir());
  const json queued = last_json(third.client("status " + interrupted + " --json"));
  EXPECT_TRUE(queued["state"] == "QUEUED" || queued["state"] == "RUNNING") << queued.dump();
  EXPECT_LE(queued["attempts"].get<int>(), attempts);
  ASSERT_EQ(third.client("cancel " + interrupted).exit_code, 0);
  EXPECT_EQ(last_json(third.client("wait " + interrupted + " --json"))["state"], "CANCELLED");
}

// Ctrl-C in `isocorr match --server` cancels the job on the server.
TEST_F(Service, InterruptedRemoteMatchCancelsTheJob) {
  ServerProcess server(data_dir());
  const std::string sphere = path("sphere.off").string();
  const pid_t client = spawn_command(std::string(ISOCORR_CLI_PATH) + " match " + sphere + " " + sphere + " -o " +
                                         (data_dir() / "never.map").string() + " --server " + server.address(),
                                     data_dir() / "client.log");
  std::string job;
  for (int i = 0; i < 600 && job.empty(); ++i) {
    const json listed = last_json(server.client("list --json"));
    if (listed.value("state", "") == "RUNNING") job = listed["name"];
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_FALSE(job.empty()) << "the client's job never ran";
  kill(client, SIGINT);
  EXPECT_EQ(wait_for_exit(client), 4);
  EXPECT_EQ(last_json(server.client("status " + job + " --json"))["state"], "CANCELLED");
  EXPECT_FALSE(fs::exists(data_dir() / "never.map"));
}

// TLS with a self-signed certificate for 127.0.0.1, and a token over it.
TEST_F(Service, TlsWithToken) {
  const fs::path cert = data_dir().string() + ".crt", key = data_dir().string() + ".key";
  const CommandRun made = run_command("openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=127.0.0.1"
                                      " -addext subjectAltName=IP:127.0.0.1 -keyout " + key.string() +
                                      " -out " + cert.string());
  ASSERT_EQ(made.exit_code, 0) << made.err;
  ServerProcess server(data_dir(), {"--tls-cert", cert.string(), "--tls-key", key.string(), "--token-file",
                                    path("token").string()});
  EXPECT_EQ(server.client("health --tls-ca " + cert.string()).exit_code, 0);
  EXPECT_EQ(server.client("list --tls-ca " + cert.string() + " --token-file " + path("token").string()).exit_code, 0);
  EXPECT_EQ(server.client("list --tls-ca " + cert.string()).exit_code, 5);
  EXPECT_EQ(server.client("health").exit_code, 3);  // plaintext client, TLS server
}

// Another gRPC implementation (Python's) with stubs generated from the .proto, reflection.
TEST_F(Service, PythonGrpcClientUsesTheApi) {
  ServerProcess server(data_dir());
  const CommandRun run = run_command(python_grpc_command("python_client_test.py", server.address(),
                                                         data_dir() / "python") +
                                     " --mesh " + path("creature.ply").string() + " --target " +
                                     path("creature_moved.ply").string());
  EXPECT_EQ(run.exit_code, 0) << run.out << run.err;
}

}  // namespace
}  // namespace isocorr::testing

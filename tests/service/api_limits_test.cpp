// What isocorr-server refuses and how it ends: bounded strings and pages, strict page
// tokens, upload sizes and the budget of uploads in progress, reflection behind a token,
// the port it listens on, and clients that lose the server while following a job. The
// real server and client on loopback; a raw gRPC stub sends what the client never would.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "api/paging.h"
#include "api/request_limits.h"
#include "api/upload_budget.h"
#include "client_json.h"
#include "google/rpc/error_details.pb.h"
#include "google/rpc/status.pb.h"
#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/sha256.h"
#include "isocorr/v1/isocorr.grpc.pb.h"
#include "server_process.h"
#include "suite_files.h"

namespace isocorr::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Far above the 8 KiB of metadata a client accepts: an error quoting it would not fit.
// (Two of them still fit in one shell command line for the real client.)
const std::string kHugeValue(60 * 1024, 'x');
constexpr size_t kShortMessage = 400;

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string sha256_of(const std::string& bytes) {
  Sha256 hasher;
  hasher.update(bytes);
  return hasher.hex_digest();
}

// Polls (bounded) until `path` holds `text`.
bool wait_for_text(const fs::path& path, const std::string& text) {
  for (int i = 0; i < 1200; ++i) {
    if (file_bytes(path).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

// The TCP ports process `pid` listens on: its socket inodes, found in /proc/net/tcp{,6}.
std::set<int> listening_ports(pid_t pid) {
  std::set<std::string> inodes;
  for (const auto& fd : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd")) {
    std::error_code error;
    const std::string target = fs::read_symlink(fd.path(), error).string();
    if (target.rfind("socket:[", 0) == 0) inodes.insert(target.substr(8, target.size() - 9));
  }
  std::set<int> ports;
  for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
    std::ifstream in(table);
    std::string line;
    std::getline(in, line);  // column titles
    while (std::getline(in, line)) {
      std::istringstream fields(line);
      std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
      fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode;
      if (state == "0A" && inodes.count(inode)) ports.insert(std::stoi(local.substr(local.find(':') + 1), nullptr, 16));
    }
  }
  return ports;
}

// The AIP-193 details of an error status: its ErrorInfo and BadRequest field violations.
struct StatusDetails {
  bool parsed = false;
  int error_infos = 0;
  google::rpc::ErrorInfo info;
  std::vector<std::string> fields;  // of the BadRequest violations
};

StatusDetails details_of(const grpc::Status& status) {
  StatusDetails details;
  google::rpc::Status proto;
  details.parsed = proto.ParseFromString(status.error_details()) && proto.code() == status.error_code() &&
                   proto.message() == status.error_message();
  for (const auto& any : proto.details()) {
    google::rpc::BadRequest bad_request;
    if (any.UnpackTo(&details.info)) ++details.error_infos;
    if (any.UnpackTo(&bad_request))
      for (const auto& violation : bad_request.field_violations()) details.fields.push_back(violation.field());
  }
  return details;
}

// Calls the API directly, with requests the isocorr client would never send.
class RawApi {
 public:
  explicit RawApi(const std::string& address)
      : channel_(grpc::CreateChannel(address, grpc::InsecureChannelCredentials())),
        meshes_(v1::MeshService::NewStub(channel_)),
        jobs_(v1::JobService::NewStub(channel_)) {}

  static std::unique_ptr<grpc::ClientContext> context() {
    auto context = std::make_unique<grpc::ClientContext>();
    context->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    return context;
  }
  v1::MeshService::Stub& meshes() { return *meshes_; }
  v1::JobService::Stub& jobs() { return *jobs_; }

  // Uploads `bytes` under a header with these fields.
  grpc::Status upload(const std::string& sha256, const std::string& filename, int64_t size_bytes,
                      const std::string& bytes) {
    auto call = context();
    v1::UploadMeshResponse response;
    auto writer = meshes_->UploadMesh(call.get(), &response);
    v1::UploadMeshRequest request;
    request.mutable_header()->set_sha256(sha256);
    request.mutable_header()->set_filename(filename);
    request.mutable_header()->set_size_bytes(size_bytes);
    if (writer->Write(request)) {
      request.set_chunk(bytes);
      if (writer->Write(request)) writer->WritesDone();
    }
    return writer->Finish();
  }

  grpc::Status list_meshes(const std::string& page_token, int page_size, v1::ListMeshesResponse* response) {
    v1::ListMeshesRequest request;
    request.set_page_token(page_token);
    request.set_page_size(page_size);
    return meshes_->ListMeshes(context().get(), request, response);
  }

 private:
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::MeshService::Stub> meshes_;
  std::unique_ptr<v1::JobService::Stub> jobs_;
};

class ApiLimits : public WithSuiteFiles<ApiLimits> {
 protected:
  static void SetUpTestSuite() {
    make_suite_dir("isocorr_api_limits_test");
    const TriangleMesh creature = limbed_blob(3);
    write_ply(path("creature.ply").string(), creature);
    write_ply(path("creature_moved.ply").string(), rotated_scaled_renumbered(creature, 1.3, 7).mesh);
    write_ply(path("sphere.ply").string(), icosphere(7));  // jobs on it run long enough to interrupt
    std::ofstream(path("token")) << "s3cret-token\n";
  }

  // Submits a job on the sphere and polls (bounded) until it runs: it keeps the only
  // worker busy for longer than any of these tests needs.
  static std::string start_long_job(const ServerProcess& server) {
    const std::string sphere = path("sphere.ply").string();
    const CommandRun submit = server.client("submit " + sphere + " " + sphere + " --json");
    EXPECT_EQ(submit.exit_code, 0) << submit.err;
    const std::string job = last_json(submit).value("name", "");
    for (int i = 0; i < 1200; ++i) {
      if (last_json(server.client("status " + job + " --json")).value("state", "") == "RUNNING") return job;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    ADD_FAILURE() << job << " never started";
    return job;
  }

  std::string reflection_probe(const ServerProcess& server) const {
    const CommandRun run =
        run_command(python_grpc_command("reflection_probe.py", server.address(), data_dir() / "python"));
    EXPECT_EQ(run.exit_code, 0) << run.err;
    return run.out;
  }

};

// README: reflection is off when a token is required (it cannot check one); health stays open.
TEST_F(ApiLimits, ReflectionIsOffWhenATokenIsRequired) {
  ServerProcess guarded(data_dir(), {"--token-file", path("token").string()});
  const std::string refused = reflection_probe(guarded);
  EXPECT_NE(refused.find("list_services: UNIMPLEMENTED"), std::string::npos) << refused;
  EXPECT_NE(refused.find("file_containing_symbol: UNIMPLEMENTED"), std::string::npos) << refused;
  EXPECT_EQ(guarded.client("health").exit_code, 0);

  ServerProcess open(data_dir() / "open");
  const std::string answered = reflection_probe(open);
  EXPECT_NE(answered.find("list_services: answered"), std::string::npos) << answered;
  EXPECT_NE(answered.find("isocorr.v1.MeshService"), std::string::npos) << answered;
  EXPECT_NE(answered.find("file_containing_symbol: answered"), std::string::npos) << answered;
}

// A 3 MiB file name once made every later ListMeshes too large for the client to receive.
TEST_F(ApiLimits, LongStringsAreRefusedQuotingOnlyAShortPrefix) {
  ServerProcess server(data_dir());
  RawApi api(server.address());
  const std::string bytes = file_bytes(path("creature.ply"));
  const std::string digest = sha256_of(bytes);
  for (int i = 0; i < 2; ++i) {
    const grpc::Status huge = api.upload(digest, std::string(3 << 20, 'n') + ".ply", bytes.size(), bytes);
    EXPECT_EQ(huge.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_LT(huge.error_message().size(), kShortMessage);
  }
  EXPECT_EQ(api.upload(digest, "two\nlines.ply", bytes.size(), bytes).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  const grpc::Status bad_digest = api.upload(kHugeValue, "a.ply", bytes.size(), bytes);
  EXPECT_EQ(bad_digest.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_LT(bad_digest.error_message().size(), kShortMessage);
  // The longest accepted file name.
  const std::string longest = std::string(251, 'n') + ".ply";
  ASSERT_TRUE(api.upload(digest, longest, bytes.size(), bytes).ok());

  const CommandRun listed = server.client("list meshes --json");
  ASSERT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_EQ(last_json(listed)["filename"], longest);

  // Every name the client passes on, through the real client.
  for (const std::string& arguments :
       {"status meshes/" + kHugeValue, "status jobs/" + kHugeValue, "watch jobs/" + kHugeValue,
        "wait jobs/" + kHugeValue, "cancel jobs/" + kHugeValue, "download jobs/" + kHugeValue + " -o x.map",
        "delete meshes/" + kHugeValue, "submit meshes/" + kHugeValue + " meshes/" + kHugeValue}) {
    const CommandRun run = server.client(arguments + " --json");
    EXPECT_EQ(run.exit_code, 2) << arguments.substr(0, 20) << run.err.substr(0, 500);
    EXPECT_EQ(error_code(run), "INVALID_ARGUMENT") << arguments.substr(0, 20);
  }
  v1::GetJobRequest request;
  request.set_name("jobs/" + kHugeValue);
  v1::Job job;
  const grpc::Status huge_job = api.jobs().GetJob(RawApi::context().get(), request, &job);
  EXPECT_EQ(huge_job.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_LT(huge_job.error_message().size(), kShortMessage);
}

// A refused name used to reach the message and the log as it came: a newline in it wrote a
// line of its own that read like a real log entry.
TEST_F(ApiLimits, ControlCharactersInClientTextAreEscapedInMessagesAndTheLog) {
  ServerProcess server(data_dir());
  RawApi api(server.address());
  const std::string forged = "[2026-01-01 00:00:00.000] [info] [r1] forged";
  v1::GetJobRequest request;
  request.set_name(std::string("jobs/\0\x1b[2J\n", 11) + forged);
  v1::Job job;
  const grpc::Status refused = api.jobs().GetJob(RawApi::context().get(), request, &job);
  ASSERT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  const std::string& message = refused.error_message();
  EXPECT_NE(message.find("jobs/\\x00\\x1b[2J\\n[2026-01-01"), std::string::npos) << message;
  EXPECT_TRUE(std::none_of(message.begin(), message.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }))
      << message;
  const std::string bytes = file_bytes(path("creature.ply"));
  const grpc::Status filename = api.upload(sha256_of(bytes), "a\r\nb\x7f\xc2\x85.ply", bytes.size(), bytes);
  EXPECT_NE(filename.error_message().find("'a\\r\\nb\\x7f\\u0085.ply'"), std::string::npos)
      << filename.error_message();

  // Every line of the log is the server's own: none starts with the forged text, and no
  // control character but the newlines ending lines is left.
  server.terminate();
  const std::string log = file_bytes(server.log_path());
  EXPECT_NE(log.find("\\n[2026-01-01"), std::string::npos) << log;  // the refusal, escaped
  EXPECT_EQ(log.find("\n" + forged), std::string::npos) << log;
  EXPECT_EQ(log.find("\n[2026-01-01"), std::string::npos) << log;
  EXPECT_TRUE(std::none_of(log.begin(), log.end(),
                           [](char c) { return (static_cast<unsigned char>(c) < 0x20 && c != '\n') || c == 0x7f; }))
      << log;
}

TEST(EscapeText, ControlCharactersAndBytesThatAreNotUtf8) {
  constexpr char kRaw[] = "a\0b\tc\x1b[0m\xc2\x85\xe2\x80\xa8\xff\xc3(\xed\xa0\x80 \\n \xc3\xa9";
  const std::string raw(kRaw, sizeof kRaw - 1);
  const std::string escaped = server::escape_text(raw);
  EXPECT_EQ(escaped, "a\\x00b\\tc\\x1b[0m\\u0085\\u2028\\xff\\xc3(\\xed\\xa0\\x80 \\n \xc3\xa9");
  EXPECT_EQ(server::escape_text(escaped), escaped);  // escaping twice changes nothing
}

// AIP-193: every error carries google.rpc.Status details, an ErrorInfo with a reason and
// the domain, and for a bad request field a BadRequest violation naming it.
TEST_F(ApiLimits, ErrorsCarryErrorInfoAndBadRequestDetails) {
  ServerProcess server(data_dir());
  RawApi api(server.address());

  v1::CreateMatchJobRequest create;
  create.set_source_mesh("meshes/" + std::string(64, 'a'));
  create.set_target_mesh("meshes/" + std::string(64, 'b'));
  create.mutable_settings()->set_level0_samples(2);
  v1::Job job;
  const grpc::Status bad_setting = api.jobs().CreateMatchJob(RawApi::context().get(), create, &job);
  ASSERT_EQ(bad_setting.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  StatusDetails details = details_of(bad_setting);
  EXPECT_TRUE(details.parsed);
  EXPECT_EQ(details.error_infos, 1);
  EXPECT_EQ(details.info.reason(), "INVALID_SETTING");
  EXPECT_EQ(details.info.domain(), "isocorr.dev");
  EXPECT_EQ(details.info.metadata().at("field"), "settings.level0_samples");
  EXPECT_EQ(details.info.metadata().at("request_id").substr(0, 1), "r");
  EXPECT_EQ(details.fields, std::vector<std::string>{"settings.level0_samples"});
  // A check across fields names the one it reports.
  create.mutable_settings()->clear_level0_samples();
  create.mutable_settings()->set_min_tracked(5);
  create.mutable_settings()->set_max_tracked(4);
  details = details_of(api.jobs().CreateMatchJob(RawApi::context().get(), create, &job));
  EXPECT_EQ(details.fields, std::vector<std::string>{"settings.max_tracked"});

  create.clear_settings();
  create.set_source_mesh("meshes/xyz");
  details = details_of(api.jobs().CreateMatchJob(RawApi::context().get(), create, &job));
  EXPECT_EQ(details.info.reason(), "INVALID_NAME");
  EXPECT_EQ(details.fields, std::vector<std::string>{"source_mesh"});

  v1::ListMeshesResponse meshes;
  details = details_of(api.list_meshes("-1", 0, &meshes));
  EXPECT_EQ(details.info.reason(), "INVALID_PAGE_TOKEN");
  EXPECT_EQ(details.fields, std::vector<std::string>{"page_token"});

  // Not a bad field: an ErrorInfo, no BadRequest.
  v1::GetJobRequest get;
  get.set_name("jobs/0123456789abcdef");
  const grpc::Status unknown = api.jobs().GetJob(RawApi::context().get(), get, &job);
  ASSERT_EQ(unknown.error_code(), grpc::StatusCode::NOT_FOUND);
  details = details_of(unknown);
  EXPECT_TRUE(details.parsed);
  EXPECT_EQ(details.info.reason(), "NOT_FOUND");
  EXPECT_EQ(details.info.domain(), "isocorr.dev");
  EXPECT_TRUE(details.fields.empty());

  // The client shows the field, and --json has the reason and the violations.
  const CommandRun submit = server.client("submit " + path("creature.ply").string() + " " +
                                          path("creature_moved.ply").string() + " --level0-samples 2 --json");
  EXPECT_EQ(submit.exit_code, 2);
  EXPECT_NE(submit.err.find("cannot create the job: settings.level0_samples: "), std::string::npos) << submit.err;
  const json error = last_json(submit)["error"];
  EXPECT_EQ(error.value("reason", ""), "INVALID_SETTING") << error.dump();
  EXPECT_EQ(error["field_violations"][0].value("field", ""), "settings.level0_samples") << error.dump();
}

// Landmarks travel in the request's settings: a bad entry is refused at creation, naming
// it, and a good list stays with the job: in its record, its report and its map, across a
// restart of the server.
TEST_F(ApiLimits, LandmarksAreCheckedAtCreationAndKeptWithTheJob) {
  const std::vector<int> truth = rotated_scaled_renumbered(limbed_blob(3), 1.3, 7).permutation;
  std::string job;
  {
    ServerProcess server(data_dir());
    RawApi api(server.address());
    v1::CreateMatchJobRequest create;
    create.set_source_mesh(last_json(server.client("upload " + path("creature.ply").string() + " --json"))["mesh"]["name"]);
    create.set_target_mesh(
        last_json(server.client("upload " + path("creature_moved.ply").string() + " --json"))["mesh"]["name"]);
    auto add = [&](int source_vertex, int target_vertex) {
      v1::Landmark* landmark = create.mutable_settings()->add_landmarks();
      landmark->set_source_vertex(source_vertex);
      landmark->set_target_vertex(target_vertex);
    };
    add(0, truth[0]);
    add(5, truth[5]);
    add(5, truth[6]);
    v1::Job created;
    const grpc::Status contradictory = api.jobs().CreateMatchJob(RawApi::context().get(), create, &created);
    ASSERT_EQ(contradictory.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(contradictory.error_message().find("landmarks[2]: source vertex 5 is given two targets"),
              std::string::npos)
        << contradictory.error_message();
    EXPECT_EQ(details_of(contradictory).fields, std::vector<std::string>{"settings.landmarks[2]"});

    create.mutable_settings()->mutable_landmarks(2)->set_source_vertex(100000);
    const grpc::Status beyond = api.jobs().CreateMatchJob(RawApi::context().get(), create, &created);
    ASSERT_EQ(beyond.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    EXPECT_NE(beyond.error_message().find("landmarks[2]: source vertex 100000 is out of range"), std::string::npos)
        << beyond.error_message();

    create.mutable_settings()->mutable_landmarks()->RemoveLast();
    ASSERT_TRUE(api.jobs().CreateMatchJob(RawApi::context().get(), create, &created).ok());
    job = created.name();
    EXPECT_EQ(last_json(server.client("wait " + job + " --json"))["state"], "SUCCEEDED");
  }
  ServerProcess server(data_dir());
  RawApi api(server.address());
  v1::GetJobRequest get;
  get.set_name(job);
  v1::Job kept;
  ASSERT_TRUE(api.jobs().GetJob(RawApi::context().get(), get, &kept).ok());
  ASSERT_EQ(kept.settings().landmarks_size(), 2);
  EXPECT_EQ(kept.settings().landmarks(1).source_vertex(), 5);
  EXPECT_EQ(kept.settings().landmarks(1).target_vertex(), truth[5]);
  const fs::path map = data_dir() / "landmarks.map", report = data_dir() / "landmarks.json";
  const CommandRun download = server.client("download " + job + " -o " + map.string() + " --report " + report.string());
  ASSERT_EQ(download.exit_code, 0) << download.err;
  std::ifstream in(report);
  const json kept_report = json::parse(in);
  EXPECT_EQ(kept_report["settings"]["landmarks"].size(), 2u);
  EXPECT_EQ(kept_report["landmarks"]["chosen_map_honours_them"], true);
  std::ifstream forward(map);
  int image_of_0 = -1;
  forward >> image_of_0;
  EXPECT_EQ(image_of_0, truth[0]);
}

TEST_F(ApiLimits, PageTokensParseStrictly) {
  ServerProcess server(data_dir());
  RawApi api(server.address());
  for (const char* file : {"creature.ply", "creature_moved.ply"})
    ASSERT_EQ(server.client(std::string("upload ") + path(file).string()).exit_code, 0);

  for (const std::string token : {"-1", " 5", "5abc", "1e3", "05", "+1", "0x1", "99999999999999999999999", ""}) {
    if (token.empty()) continue;
    v1::ListMeshesResponse meshes;
    EXPECT_EQ(api.list_meshes(token, 0, &meshes).error_code(), grpc::StatusCode::INVALID_ARGUMENT) << token;
    v1::ListJobsRequest request;
    request.set_page_token(token);
    v1::ListJobsResponse jobs;
    EXPECT_EQ(api.jobs().ListJobs(RawApi::context().get(), request, &jobs).error_code(),
              grpc::StatusCode::INVALID_ARGUMENT)
        << token;
  }
  v1::ListMeshesResponse first, second, past_the_end;
  ASSERT_TRUE(api.list_meshes("", 1, &first).ok());
  ASSERT_EQ(first.meshes_size(), 1);
  EXPECT_EQ(first.next_page_token(), "1");
  ASSERT_TRUE(api.list_meshes(first.next_page_token(), 1, &second).ok());
  ASSERT_EQ(second.meshes_size(), 1);
  EXPECT_NE(second.meshes(0).name(), first.meshes(0).name());
  EXPECT_EQ(second.next_page_token(), "");
  ASSERT_TRUE(api.list_meshes("7", 0, &past_the_end).ok());
  EXPECT_EQ(past_the_end.meshes_size(), 0);
}

// Pages end at a byte budget too: a thousand large items never make a 4 MiB message.
TEST(ListPages, EndAtTheByteBudgetWithAtLeastOneItem) {
  auto mesh_with_filename_bytes = [](size_t bytes) {
    v1::Mesh mesh;
    mesh.set_filename(std::string(bytes, 'f'));
    return mesh;
  };
  v1::ListMeshesResponse page;
  const std::string next =
      server::fill_page(*page.mutable_meshes(), 1000, 1000, "", [&](size_t) { return mesh_with_filename_bytes(4000); });
  EXPECT_LT(page.meshes_size(), 1000);
  EXPECT_GT(page.meshes_size(), 100);
  EXPECT_LE(page.ByteSizeLong(), server::kMaxPageBytes);
  EXPECT_EQ(next, std::to_string(page.meshes_size()));

  v1::ListMeshesResponse single;
  const std::string after = server::fill_page(*single.mutable_meshes(), 3, 0, "1", [&](size_t) {
    return mesh_with_filename_bytes(2 * server::kMaxPageBytes);
  });
  EXPECT_EQ(single.meshes_size(), 1);  // an item above the budget still makes progress
  EXPECT_EQ(after, "2");
}

TEST_F(ApiLimits, UploadSizeMustBeTheBytesSent) {
  ServerProcess server(data_dir());
  RawApi api(server.address());
  const std::string bytes = file_bytes(path("creature.ply"));
  const std::string digest = sha256_of(bytes);
  const int64_t size = static_cast<int64_t>(bytes.size());
  for (const int64_t declared : {int64_t{10}, int64_t{-1}, int64_t{0}, size - 1, size + 1}) {
    const grpc::Status status = api.upload(digest, "creature.ply", declared, bytes);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << declared << ": " << status.error_message();
  }
  EXPECT_EQ(server.client("list meshes").out, "");
  EXPECT_TRUE(api.upload(digest, "creature.ply", size, bytes).ok());
}

// Uploads in progress hold the memory their declared sizes can take; past --upload-memory a
// new one is refused with RESOURCE_EXHAUSTED until they are done.
TEST_F(ApiLimits, UploadsInProgressShareABudget) {
  const std::string held = file_bytes(path("creature.ply")), other = file_bytes(path("creature_moved.ply"));
  const int64_t per_byte = server::UploadBudget::kMemoryPerFileByte;
  const int64_t budget = per_byte * static_cast<int64_t>(held.size() + other.size()) - 1;
  ServerProcess server(data_dir(), {"--max-mesh-bytes", std::to_string(std::max(held.size(), other.size())),
                                    "--upload-memory", std::to_string(budget)});
  RawApi api(server.address());
  auto context = RawApi::context();
  v1::UploadMeshResponse response;
  auto holder = api.meshes().UploadMesh(context.get(), &response);
  v1::UploadMeshRequest request;
  request.mutable_header()->set_sha256(sha256_of(held));
  request.mutable_header()->set_filename("creature.ply");
  request.mutable_header()->set_size_bytes(static_cast<int64_t>(held.size()));
  ASSERT_TRUE(holder->Write(request));
  holder->WaitForInitialMetadata();  // the server sends it once the upload holds its bytes

  const CommandRun refused = server.client("upload " + path("creature_moved.ply").string() + " --json");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_EQ(error_code(refused), "RESOURCE_EXHAUSTED");
  EXPECT_NE(refused.err.find("--upload-memory"), std::string::npos) << refused.err;

  request.set_chunk(held);
  ASSERT_TRUE(holder->Write(request));
  holder->WritesDone();
  const grpc::Status finished = holder->Finish();
  ASSERT_TRUE(finished.ok()) << finished.error_message();
  const CommandRun accepted = server.client("upload " + path("creature_moved.ply").string());
  EXPECT_EQ(accepted.exit_code, 0) << accepted.err;

  // A budget below the largest mesh would refuse every upload of that size: not started.
  const CommandRun misconfigured =
      run_command(std::string(ISOCORR_SERVER_PATH) + " --listen 127.0.0.1:0 --data-dir " +
                  (data_dir() / "never").string() + " --max-mesh-bytes 1000 --upload-memory 17999");
  EXPECT_EQ(misconfigured.exit_code, 1);
}

// `--port-file pf.txt` (no directory) used to write the port and then fail; and the
// server listens on the port it reports, and on no other.
TEST_F(ApiLimits, PortFileMayBeABareFileNameAndOnlyThatPortListens) {
  const fs::path dir = data_dir();
  fs::create_directories(dir);
  const pid_t server = spawn_command("/bin/sh -c 'cd " + dir.string() + " && exec " + ISOCORR_SERVER_PATH +
                                         " --listen 127.0.0.1:0 --data-dir data --port-file pf.txt'",
                                     dir / "server.log");
  ASSERT_TRUE(wait_for_text(dir / "pf.txt", "\n")) << file_bytes(dir / "server.log");
  const int port = std::stoi(file_bytes(dir / "pf.txt"));
  const CommandRun health =
      run_command(std::string(ISOCORR_CLI_PATH) + " health --server 127.0.0.1:" + std::to_string(port));
  EXPECT_EQ(health.exit_code, 0) << health.err << file_bytes(dir / "server.log");
  EXPECT_EQ(listening_ports(server), std::set<int>{port});
  kill(server, SIGTERM);
  EXPECT_EQ(wait_for_exit(server), 0) << file_bytes(dir / "server.log");
}

// `mesh` with its coordinates scaled so that the largest is `largest`, as an OFF file.
void write_scaled_off(const TriangleMesh& mesh, double largest, const fs::path& file) {
  double now = 0;
  for (const Vec3& p : mesh.vertices) now = std::max(now, p.cwiseAbs().maxCoeff());
  std::ofstream out(file);
  out.precision(17);
  out << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
  for (const Vec3& p : mesh.vertices) out << p.x() / now * largest << ' ' << p.y() / now * largest << ' ' << p.z() / now * largest << '\n';
  for (const Face& f : mesh.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

// The example pair scaled to coordinates of +-1e308 once sent its job's eigensolver into an
// endless loop that neither CancelJob nor SIGTERM stopped, and at 1e-160 it was refused as
// having no faces left: both now give the map of the unscaled pair. And a server told to stop
// while a job runs ends within its grace period (a second SIGTERM at once).
TEST_F(ApiLimits, MeshesAtTheLimitsOfDoubleMatchLikeTheirUnscaledCopiesAndNeverHoldTheServer) {
  ServerProcess server(data_dir(), {"--threads", "1", "--shutdown-grace", "2"});
  const fs::path reference = data_dir() / "reference.map";
  const CommandRun unscaled = server.client("match " + path("creature.ply").string() + " " +
                                            path("creature_moved.ply").string() + " -o " + reference.string());
  ASSERT_EQ(unscaled.exit_code, 0) << unscaled.err;
  const TriangleMesh creature = limbed_blob(3);
  const TriangleMesh moved = rotated_scaled_renumbered(creature, 1.3, 7).mesh;
  for (const double largest : {1e308, 1e-160}) {
    const std::string tag = largest > 1 ? "huge" : "tiny";
    const fs::path source = data_dir() / (tag + "_source.off"), target = data_dir() / (tag + "_target.off");
    write_scaled_off(creature, largest, source);
    write_scaled_off(moved, largest, target);
    const fs::path map = data_dir() / (tag + ".map");
    const CommandRun scaled =
        server.client("match " + source.string() + " " + target.string() + " -o " + map.string() + " --timeout 300");
    ASSERT_EQ(scaled.exit_code, 0) << tag << ": " << scaled.err;
    EXPECT_EQ(file_bytes(map), file_bytes(reference)) << tag;
  }

  start_long_job(server);
  server.send_signal(SIGTERM);
  EXPECT_NE(server.wait_for_exit(30), -1) << "still running 30 s after SIGTERM with a 2 s grace period";
}

// A job running past the server's time limit fails with DEADLINE_EXCEEDED and frees its worker.
TEST_F(ApiLimits, AJobPastTheTimeLimitFailsWithDeadlineExceeded) {
  ServerProcess server(data_dir(), {"--threads", "1", "--job-time-limit", "1"});
  const std::string job = start_long_job(server);
  json status;
  for (int i = 0; i < 1200; ++i) {
    status = last_json(server.client("status " + job + " --json"));
    if (status.value("done", false)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_EQ(status.value("state", ""), "FAILED") << status.dump();
  EXPECT_EQ(status["error"].value("code", 0), 4) << status.dump();  // DEADLINE_EXCEEDED
  EXPECT_NE(status["error"].value("message", "").find("--job-time-limit"), std::string::npos) << status.dump();
}

// A second SIGTERM ends a stopping server at once, whatever its workers are doing.
TEST_F(ApiLimits, ASecondSigtermEndsAStoppingServerAtOnce) {
  ServerProcess server(data_dir(), {"--threads", "1", "--shutdown-grace", "60"});
  start_long_job(server);
  server.send_signal(SIGTERM);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  server.send_signal(SIGTERM);
  EXPECT_NE(server.wait_for_exit(20), -1) << "still running 20 s after a second SIGTERM";
}

// A server stopping (SIGTERM) under a watch and a match: their job was not cancelled, so
// the clients say "unavailable" (exit 3), name the job and how to follow it again.
TEST_F(ApiLimits, ClientsFollowingAJobSayItGoesOnWhenTheServerStops) {
  ServerProcess server(data_dir(), {"--threads", "1"});
  const std::string running = start_long_job(server);
  const fs::path watch_log = data_dir() / "watch.log", match_log = data_dir() / "match.log";
  const pid_t watch = spawn_command(std::string(ISOCORR_CLI_PATH) + " watch " + running + " --json --server " +
                                        server.address(),
                                    watch_log);
  // Queued behind the running job; waits 3 s for the server to come back, then gives up.
  const pid_t match = spawn_command(std::string(ISOCORR_CLI_PATH) + " match " + path("creature.ply").string() + " " +
                                        path("creature_moved.ply").string() + " -o " +
                                        (data_dir() / "never.map").string() + " --timeout 3 --server " +
                                        server.address(),
                                    match_log);
  ASSERT_TRUE(wait_for_text(watch_log, "\"state\":\"RUNNING\"")) << file_bytes(watch_log);
  ASSERT_TRUE(wait_for_text(match_log, " on " + server.address())) << file_bytes(match_log);
  const std::string queued = last_json(server.client("list --json"))["name"];
  // Not awaited: the server's own exit waits for the running job's next safe point.
  server.send_signal(SIGTERM);

  EXPECT_EQ(wait_for_exit(watch), 3) << file_bytes(watch_log);
  EXPECT_NE(file_bytes(watch_log).find("the server is stopping"), std::string::npos) << file_bytes(watch_log);
  EXPECT_EQ(wait_for_exit(match), 3) << file_bytes(match_log);
  for (const auto& [log, job] : {std::pair{watch_log, running}, std::pair{match_log, queued}}) {
    const std::string text = file_bytes(log);
    EXPECT_EQ(text.find("CANCELLED"), std::string::npos) << text;
    EXPECT_NE(text.find("goes on"), std::string::npos) << text;
    EXPECT_NE(text.find("isocorr watch " + job), std::string::npos) << text;
  }
  EXPECT_FALSE(fs::exists(data_dir() / "never.map"));
}

// A server killed under a watch and a match: the watch exits 3 at once; the match waits for
// the server to come back on its address, follows its job again and writes the map.
TEST_F(ApiLimits, RemoteMatchFollowsItsJobAcrossACrash) {
  auto server = std::make_unique<ServerProcess>(data_dir(), std::vector<std::string>{"--threads", "1"});
  const std::string address = server->address();
  const std::string blocker = start_long_job(*server);
  const fs::path watch_log = data_dir() / "watch.log", match_log = data_dir() / "match.log";
  const fs::path map = data_dir() / "resumed.map";
  const pid_t watch = spawn_command(std::string(ISOCORR_CLI_PATH) + " watch " + blocker + " --server " + address,
                                    watch_log);
  const pid_t match = spawn_command(std::string(ISOCORR_CLI_PATH) + " match " + path("creature.ply").string() + " " +
                                        path("creature_moved.ply").string() + " -o " + map.string() +
                                        " --timeout 120 --server " + address,
                                    match_log);
  ASSERT_TRUE(wait_for_text(match_log, " on " + address)) << file_bytes(match_log);
  ASSERT_TRUE(wait_for_text(watch_log, "stage preprocess")) << file_bytes(watch_log);
  server->kill_hard();
  EXPECT_EQ(wait_for_exit(watch), 3) << file_bytes(watch_log);
  EXPECT_NE(file_bytes(watch_log).find("isocorr watch " + blocker), std::string::npos) << file_bytes(watch_log);

  ASSERT_TRUE(wait_for_text(match_log, "waiting up to")) << file_bytes(match_log);
  // One start allowed: the interrupted long job is given up, so the match's job runs at once.
  server = std::make_unique<ServerProcess>(
      data_dir(), std::vector<std::string>{"--threads", "1", "--max-attempts", "1", "--listen", address});
  EXPECT_EQ(wait_for_exit(match), 0) << file_bytes(match_log);
  EXPECT_NE(file_bytes(match_log).find("is back"), std::string::npos) << file_bytes(match_log);
  std::ifstream written(map);
  int entries = 0;
  for (int index; written >> index;) ++entries;
  EXPECT_EQ(entries, limbed_blob(3).num_vertices());
}

}  // namespace
}  // namespace isocorr::testing

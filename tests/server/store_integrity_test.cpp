// The data directory checked when read and when writes fail: a changed byte in a stored
// mesh, result or job record is noticed (DATA_LOSS), set aside in quarantine/ and, for a
// mesh, repaired by uploading the right bytes; a full disk (a file-size limit here) is
// RESOURCE_EXHAUSTED without server paths and leaves no temporary file behind.
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <climits>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/util/sha256.h"
#include "service_error.h"
#include "storage/durable_file.h"
#include "storage/job_journal.h"
#include "storage_test_support.h"
#include "storage/mesh_store.h"

namespace isocorr::server {
namespace {

namespace fs = std::filesystem;
using Kind = ServiceError::Kind;


// Changes one byte in the middle of a file, as a failing disk or a stray edit would.
void flip_byte(const fs::path& path) {
  std::string bytes = read_whole_file(path);
  bytes[bytes.size() / 2] ^= 0x01;
  std::ofstream(path, std::ios::binary) << bytes;
}

// The kind of the ServiceError `body` throws (fails the test when it throws none).
template <typename Body>
Kind kind_thrown(Body body, std::string* message = nullptr) {
  try {
    body();
  } catch (const ServiceError& e) {
    if (message) *message = e.what();
    return e.kind();
  }
  ADD_FAILURE() << "no ServiceError thrown";
  return Kind::kInvalidArgument;
}

// Regular files written by this process fail beyond `bytes` (EFBIG) while it lives.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    signal(SIGXFSZ, SIG_IGN);
    getrlimit(RLIMIT_FSIZE, &saved_);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() { setrlimit(RLIMIT_FSIZE, &saved_); }

 private:
  rlimit saved_{};
};

std::vector<fs::path> files_ending(const fs::path& dir, const std::string& suffix) {
  std::vector<fs::path> found;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
      found.push_back(entry.path());
  }
  return found;
}

class StoreIntegrity : public DataDirTest {
 protected:
  StoreIntegrity() : DataDirTest("isocorr_integrity_test_") {}

  static MeshInfo upload(MeshStore& store, const std::string& bytes) { return upload_mesh(store, bytes, "ball.off"); }

  static MatchOutput small_result() {
    MatchOutput result;
    result.forward = {2, 0, 1, 1};
    result.reverse = {1, 2, 0};
    result.forward_confidence = {0.5f, 0.25f, 0.125f, 1.f};
    result.reverse_confidence = {0.f, 1.f, 2.f};
    result.report_json = "{\"final\":{}}";
    return result;
  }

  // At two starts in a row, the journal's only job is `id`, FAILED with DATA_LOSS saying `why`.
  void expect_reported_lost(const std::string& id, const std::string& why) {
    for (int start = 0; start < 2; ++start) {
      JobJournal journal(dir_);
      const std::vector<JobRecord> jobs = journal.load_all();
      ASSERT_EQ(jobs.size(), 1u);
      EXPECT_EQ(jobs[0].id, id);
      EXPECT_EQ(jobs[0].state, JobState::kFailed);
      EXPECT_EQ(jobs[0].error_code, ErrorCode::kDataLoss);
      EXPECT_NE(jobs[0].error_message.find(why), std::string::npos) << jobs[0].error_message;
    }
  }

  // The job a result belongs to (its manifest names it).
  static JobRecord job_named(const std::string& id) {
    JobRecord job;
    job.id = id;
    job.state = JobState::kSucceeded;
    job.source_digest = std::string(64, 'a');
    job.target_digest = std::string(64, 'b');
    return job;
  }
};

TEST_F(StoreIntegrity, CorruptedMeshIsDataLossQuarantinedAndRepairedByUpload) {
  const std::string bytes = off_text(icosphere(2));
  const std::string digest = sha256_hex(bytes);
  MeshStore store(dir_, 1 << 24);
  upload(store, bytes);
  ASSERT_TRUE(store.get(digest));
  flip_byte(dir_ / "meshes" / (digest + ".mesh"));

  EXPECT_EQ(kind_thrown([&] { store.get(digest); }), Kind::kDataLoss);
  EXPECT_TRUE(fs::exists(dir_ / "quarantine" / "meshes" / (digest + ".mesh")));
  EXPECT_FALSE(fs::exists(dir_ / "meshes" / (digest + ".mesh")));
  // Still reported, by every way in, until it is uploaded again.
  EXPECT_EQ(kind_thrown([&] { store.describe(digest); }), Kind::kDataLoss);
  EXPECT_EQ(kind_thrown([&] { store.read(digest); }), Kind::kDataLoss);
  EXPECT_TRUE(store.list().empty());
  EXPECT_FALSE(store.find_intact(digest));  // so the upload path stores the bytes again

  upload(store, bytes);
  EXPECT_EQ(store.read(digest).bytes, bytes);
  EXPECT_EQ(store.list().size(), 1u);
  EXPECT_FALSE(fs::exists(dir_ / "quarantine" / "meshes" / (digest + ".mesh")));  // archived under a dated name
}

TEST_F(StoreIntegrity, TruncatedMeshAndGarbledDescriptionAreDataLoss) {
  const std::string first = off_text(icosphere(2)), second = off_text(limbed_blob(2));
  MeshStore store(dir_, 1 << 24);
  upload(store, first);
  upload(store, second);
  fs::resize_file(dir_ / "meshes" / (sha256_hex(first) + ".mesh"), first.size() - 6);
  flip_byte(dir_ / "meshes" / (sha256_hex(second) + ".json"));
  EXPECT_EQ(kind_thrown([&] { store.describe(sha256_hex(first)); }), Kind::kDataLoss);
  EXPECT_EQ(kind_thrown([&] { store.get(sha256_hex(second)); }), Kind::kDataLoss);
}

TEST_F(StoreIntegrity, UnacknowledgedUploadLeftoversAreRemovedAtStart) {
  const std::string bytes = off_text(icosphere(2));
  { MeshStore store(dir_, 1 << 24); upload(store, bytes); }
  const std::string orphan(64, 'c');
  std::ofstream(dir_ / "meshes" / (orphan + ".mesh.pending")) << "OFF";
  std::ofstream(dir_ / "meshes" / (orphan + ".json.tmp")) << "{";
  MeshStore reopened(dir_, 1 << 24);
  EXPECT_FALSE(fs::exists(dir_ / "meshes" / (orphan + ".mesh.pending")));
  EXPECT_FALSE(fs::exists(dir_ / "meshes" / (orphan + ".json.tmp")));
  EXPECT_TRUE(reopened.get(sha256_hex(bytes)));
}

TEST_F(StoreIntegrity, UploadOnFullDiskIsResourceExhaustedWithoutPathsOrLeftovers) {
  const std::string bytes = off_text(icosphere(3));
  ASSERT_GT(bytes.size(), 8192u);
  MeshStore store(dir_, 1 << 24);
  std::string message;
  {
    FileSizeLimit limit(4096);
    const Kind kind = kind_thrown([&] { upload(store, bytes); }, &message);
    EXPECT_EQ(kind, Kind::kResourceExhausted);
  }
  EXPECT_NE(message.find("disk is full"), std::string::npos) << message;
  EXPECT_EQ(message.find(dir_.string()), std::string::npos) << message;
  EXPECT_TRUE(files_ending(dir_ / "meshes", "").empty());
  EXPECT_TRUE(files_ending(dir_ / "tmp", "").empty());
  upload(store, bytes);  // works again once there is room
  EXPECT_TRUE(store.get(sha256_hex(bytes)));
}

TEST_F(StoreIntegrity, UploadWhoseDescriptionCannotBeWrittenLeavesNoMeshBehind) {
  const std::string bytes = off_text(icosphere(2));
  const std::string digest = sha256_hex(bytes);
  MeshStore store(dir_, 1 << 24);
  // The description's temporary name taken by a directory: its write fails after the
  // bytes were moved into place, as on a disk that fills up between the two.
  fs::create_directories(dir_ / "meshes" / (digest + ".json.tmp"));
  std::string message;
  EXPECT_EQ(kind_thrown([&] { upload(store, bytes); }, &message), Kind::kResourceExhausted);
  EXPECT_EQ(message.find(dir_.string()), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(dir_ / "meshes" / (digest + ".mesh")));
  EXPECT_FALSE(store.find_intact(digest));
  fs::remove(dir_ / "meshes" / (digest + ".json.tmp"));
  upload(store, bytes);
  EXPECT_TRUE(store.get(digest));
}

TEST_F(StoreIntegrity, UnreadableJobRecordBecomesAFailedJobNotAVanishedOne) {
  JobRecord job;
  job.id = "0123456789abcdef";
  job.source_digest = std::string(64, 'a');
  job.target_digest = std::string(64, 'b');
  {
    JobJournal journal(dir_);
    journal.save(job);
  }
  flip_byte(dir_ / "jobs" / (job.id + ".json"));
  expect_reported_lost(job.id, "corrupted");
  EXPECT_TRUE(fs::exists(dir_ / "quarantine" / "jobs" / (job.id + ".json")));
}

TEST_F(StoreIntegrity, AJobWhoseRecordIsLostIsReportedAsDataLossWithItsResultKept) {
  const JobRecord job = job_named("00000000000000e1");
  {
    JobJournal journal(dir_);
    journal.save(job);
    journal.save_result(job, small_result());
  }
  fs::remove(dir_ / "jobs" / (job.id + ".json"));
  expect_reported_lost(job.id, "lost");
  EXPECT_TRUE(fs::exists(dir_ / "quarantine" / "results" / job.id / "manifest.json"));
}

TEST_F(StoreIntegrity, OverwrittenResultIndexIsDataLossAndQuarantined) {
  const JobRecord job = job_named("00000000000000aa");
  const std::string& id = job.id;
  JobJournal journal(dir_);
  journal.save_result(job, small_result());
  EXPECT_EQ(journal.read_map(job, ResultPart::kForwardMap), small_result().forward);
  // A forward map with an entry overwritten by INT_MAX: the part no longer matches its digest.
  std::string forward = read_whole_file(dir_ / "results" / id / "forward.i32");
  const int huge = INT_MAX;
  std::memcpy(forward.data(), &huge, sizeof huge);
  std::ofstream(dir_ / "results" / id / "forward.i32", std::ios::binary) << forward;
  std::string message;
  EXPECT_EQ(kind_thrown([&] { journal.read_map(job, ResultPart::kForwardMap); }, &message), Kind::kDataLoss);
  EXPECT_NE(message.find("sha256"), std::string::npos) << message;
  EXPECT_TRUE(fs::exists(dir_ / "quarantine" / "results" / id / "forward.i32"));
  EXPECT_FALSE(fs::exists(dir_ / "results" / id));
  // Gone from results/: still DATA_LOSS, not an internal error.
  EXPECT_EQ(kind_thrown([&] { journal.read_report(job); }), Kind::kDataLoss);
}

TEST_F(StoreIntegrity, TruncatedResultPartIsDataLoss) {
  const JobRecord job = job_named("00000000000000bb");
  JobJournal journal(dir_);
  journal.save_result(job, small_result());
  fs::resize_file(dir_ / "results" / job.id / "reverse.i32", 6);
  std::string message;
  EXPECT_EQ(kind_thrown([&] { journal.read_map(job, ResultPart::kReverseMap); }, &message), Kind::kDataLoss);
  EXPECT_NE(message.find("6 bytes, not 12"), std::string::npos) << message;
}

TEST_F(StoreIntegrity, ResultsFromBeforeManifestsAreAdoptedOnceWhenWholeAndSetAsideWhenNot) {
  const JobRecord whole = job_named("00000000000000cc"), broken = job_named("00000000000000dd");
  {
    JobJournal journal(dir_);
    for (const JobRecord& job : {whole, broken}) {
      journal.save(job);
      journal.save_result(job, small_result());
    }
  }
  // A data directory as a server from before manifests left it: no layout file, no manifests.
  fs::remove(dir_ / "layout");
  fs::remove(dir_ / "results" / whole.id / "manifest.json");
  fs::remove(dir_ / "results" / broken.id / "manifest.json");
  std::string forward = read_whole_file(dir_ / "results" / broken.id / "forward.i32");
  const int outside = 3;  // the reverse map has 3 entries: index 3 is outside the target
  std::memcpy(forward.data(), &outside, sizeof outside);
  std::ofstream(dir_ / "results" / broken.id / "forward.i32", std::ios::binary) << forward;

  {
    JobJournal journal(dir_);  // the first start of a server that binds manifests
    EXPECT_EQ(journal.read_map(whole, ResultPart::kForwardMap), small_result().forward);
    EXPECT_EQ(journal.read_report(whole), small_result().report_json);
    EXPECT_TRUE(fs::exists(dir_ / "results" / whole.id / "manifest.json"));
    EXPECT_EQ(kind_thrown([&] { journal.read_map(broken, ResultPart::kForwardMap); }), Kind::kDataLoss);
    EXPECT_TRUE(fs::exists(dir_ / "quarantine" / "results" / broken.id / "forward.i32"));
    EXPECT_TRUE(fs::exists(dir_ / "layout"));
  }
  // Adopted once: a manifest lost after the upgrade is not made again from the parts.
  fs::remove(dir_ / "results" / whole.id / "manifest.json");
  JobJournal journal(dir_);
  EXPECT_EQ(kind_thrown([&] { journal.read_map(whole, ResultPart::kForwardMap); }), Kind::kDataLoss);
  EXPECT_FALSE(fs::exists(dir_ / "results" / whole.id / "manifest.json"));
  EXPECT_TRUE(fs::exists(dir_ / "quarantine" / "results" / whole.id / "forward.i32"));
}

TEST_F(StoreIntegrity, ResultOnFullDiskIsResourceExhaustedAndLeavesNoTemporaryDirectory) {
  MatchOutput big = small_result();
  big.forward.assign(4096, 0);
  JobJournal journal(dir_);
  {
    FileSizeLimit limit(8192);
    EXPECT_EQ(kind_thrown([&] { journal.save_result(job_named("00000000000000cc"), big); }),
              Kind::kResourceExhausted);
  }
  EXPECT_TRUE(fs::is_empty(dir_ / "results"));
  EXPECT_TRUE(files_ending(dir_ / "jobs", ".tmp").empty());
}

}  // namespace
}  // namespace isocorr::server

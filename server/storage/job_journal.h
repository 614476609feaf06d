// The durable side of jobs under <data-dir>: jobs/<id>.json holds each job's record
// (rewritten atomically on every state change), results/<id>/ its finished result.
// A job is acknowledged (CreateMatchJob returns, or SUCCEEDED is reported) only after
// the corresponding write is on disk.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "isocorr/matching/matcher.h"
#include "jobs/job_record.h"

namespace isocorr::server {

// The parts of a result, one file each (little-endian int32 / float32, JSON).
struct JobResultFiles {
  std::vector<int> forward, reverse;
  std::vector<float> forward_confidence, reverse_confidence;
  std::string report_json;
};

class JobJournal {
 public:
  explicit JobJournal(const std::filesystem::path& data_dir);

  void save(const JobRecord& job);
  std::vector<JobRecord> load_all() const;  // skips unreadable records (logged)

  // Written into a temporary directory and renamed into place, so a result is whole or absent.
  void save_result(const std::string& id, const JobResultFiles& result);
  bool has_result(const std::string& id) const;
  std::vector<int> read_indices(const std::string& id, const std::string& part) const;
  std::vector<float> read_values(const std::string& id, const std::string& part) const;
  std::string read_report(const std::string& id) const;

 private:
  std::filesystem::path jobs_dir_, results_dir_;
};

}  // namespace isocorr::server

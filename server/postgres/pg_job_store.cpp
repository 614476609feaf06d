#include "postgres/pg_job_store.h"

#include <spdlog/spdlog.h>

#include "service_error.h"
#include "storage/job_record_json.h"
#include "storage/sealed_json.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;
using nlohmann::json;

namespace {

constexpr const char* kColumns = "id, record, version, progress, create_time_ms";

std::string progress_text(const JobProgressInfo& p) {
  return json{{"stage", p.stage}, {"level", p.level}, {"levels", p.levels}, {"fraction", p.fraction}}.dump();
}

JobProgressInfo progress_from_text(const std::string& text) {
  JobProgressInfo progress;
  const json j = json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("stage")) return progress;
  progress.stage = j.value("stage", progress.stage);
  progress.level = j.value("level", 0);
  progress.levels = j.value("levels", 0);
  progress.fraction = j.value("fraction", 0.0);
  return progress;
}

// A row of kColumns as a job. A record that fails its seal is reported as a FAILED job
// (DATA_LOSS), as the local journal does, and left in the database for the operator.
JobRecord job_of(const pqxx::row& row) {
  const std::string id = row["id"].as<std::string>();
  JobRecord job;
  try {
    job = record_from_json(unseal_json(row["record"].as<std::string>()));
    if (job.id != id) throw std::runtime_error("it names another job");
  } catch (const std::exception& e) {
    spdlog::error("[job {}] its record in the database is unreadable: {}", id, e.what());
    job = JobRecord{};
    job.id = id;
    job.state = JobState::kFailed;
    job.error_code = ErrorCode::kDataLoss;
    job.error_message = "the server's record of this job is corrupted in the shared store; "
                        "its meshes, settings and result are unknown: submit the job again";
    job.create_time_ms = row["create_time_ms"].as<int64_t>();
  }
  job.version = row["version"].as<uint64_t>();
  if (job.state == JobState::kRunning) job.progress = progress_from_text(row["progress"].as<std::string>());
  return job;
}

std::string sealed(const JobRecord& job) { return seal_json(record_to_json(job)); }

}  // namespace

void PgJobStore::insert(const JobRecord& job, const std::string& replica) {
  database_.transaction([&](pqxx::work& txn) {
    txn.exec_params(
        "INSERT INTO isocorr_jobs (id, record, state, source_digest, target_digest, create_time_ms, progress, "
        "created_by) VALUES ($1, $2, $3, $4, $5, $6, $7, $8)",
        job.id, sealed(job), job_state_name(job.state), job.source_digest, job.target_digest, job.create_time_ms,
        progress_text(job.progress), replica);
  });
}

void PgJobStore::write_record(pqxx::work& txn, const JobRecord& job) {
  txn.exec_params(
      "UPDATE isocorr_jobs SET record = $2, state = $3, progress = $4, version = version + 1, "
      "claimed_by = CASE WHEN $3 = 'RUNNING' THEN claimed_by END, "
      "lease_until = CASE WHEN $3 = 'RUNNING' THEN lease_until END WHERE id = $1",
      job.id, sealed(job), job_state_name(job.state), progress_text(job.progress));
}

std::optional<JobRecord> PgJobStore::find(const std::string& id) const {
  return database_.transaction([&](pqxx::work& txn) -> std::optional<JobRecord> {
    const pqxx::result rows = txn.exec_params(std::string("SELECT ") + kColumns + " FROM isocorr_jobs WHERE id = $1", id);
    if (rows.empty()) return std::nullopt;
    return job_of(rows[0]);
  });
}

std::vector<JobRecord> PgJobStore::list() const {
  return database_.transaction([&](pqxx::work& txn) {
    std::vector<JobRecord> jobs;
    for (const auto& row : txn.exec(std::string("SELECT ") + kColumns + " FROM isocorr_jobs ORDER BY create_time_ms, id"))
      jobs.push_back(job_of(row));
    return jobs;
  });
}

int PgJobStore::count_queued() const {
  return database_.transaction(
      [](pqxx::work& txn) { return txn.exec("SELECT count(*) FROM isocorr_jobs WHERE state = 'QUEUED'")[0][0].as<int>(); });
}

std::map<JobState, int> PgJobStore::count_by_state() const {
  return database_.transaction([](pqxx::work& txn) {
    std::map<JobState, int> counts;
    for (const auto& row : txn.exec("SELECT state, count(*) FROM isocorr_jobs GROUP BY state"))
      for (JobState state : {JobState::kQueued, JobState::kRunning, JobState::kSucceeded, JobState::kFailed,
                             JobState::kCancelled})
        if (row[0].as<std::string>() == job_state_name(state)) counts[state] = row[1].as<int>();
    return counts;
  });
}

bool PgJobStore::mesh_in_use(const std::string& digest) const {
  return database_.transaction([&](pqxx::work& txn) {
    return txn
        .exec_params("SELECT EXISTS (SELECT 1 FROM isocorr_jobs WHERE state IN ('QUEUED', 'RUNNING') "
                     "AND (source_digest = $1 OR target_digest = $1))",
                     digest)[0][0]
        .as<bool>();
  });
}

JobRecord PgJobStore::cancel(const std::string& id) {
  return database_.transaction([&](pqxx::work& txn) {
    const pqxx::result rows =
        txn.exec_params(std::string("SELECT ") + kColumns + " FROM isocorr_jobs WHERE id = $1 FOR UPDATE", id);
    if (rows.empty()) throw ServiceError(Kind::kNotFound, "no job jobs/" + id + " on this server");
    JobRecord job = job_of(rows[0]);
    if (is_final(job.state))
      throw ServiceError(Kind::kFailedPrecondition,
                         "job jobs/" + id + " is already " + job_state_name(job.state) + "; nothing to cancel");
    if (job.state == JobState::kQueued) {
      job.state = JobState::kCancelled;
      job.error_code = ErrorCode::kCancelled;
      job.error_message = "cancelled before it started";
      job.end_time_ms = now_ms();
      write_record(txn, job);
      job.version += 1;
    } else {  // the replica running it sees the flag at its next renewal
      txn.exec_params("UPDATE isocorr_jobs SET cancel_requested = true WHERE id = $1", id);
    }
    return job;
  });
}

std::optional<JobRecord> PgJobStore::claim(const std::string& replica, std::chrono::milliseconds lease,
                                           int max_attempts) {
  return database_.transaction([&](pqxx::work& txn) -> std::optional<JobRecord> {
    for (;;) {
      const pqxx::result rows = txn.exec_params(
          std::string("SELECT ") + kColumns + ", state, claimed_by, cancel_requested FROM isocorr_jobs "
          "WHERE state = 'QUEUED' OR (state = 'RUNNING' AND lease_until < now()) "
          "ORDER BY created_by IS DISTINCT FROM $1, create_time_ms, id LIMIT 1 FOR UPDATE SKIP LOCKED", replica);
      if (rows.empty()) return std::nullopt;
      JobRecord job = job_of(rows[0]);
      const bool orphaned = rows[0]["state"].as<std::string>() == "RUNNING";
      if (orphaned) {
        const std::string lost_by = rows[0]["claimed_by"].is_null() ? "?" : rows[0]["claimed_by"].as<std::string>();
        if (rows[0]["cancel_requested"].as<bool>()) {
          job.state = JobState::kCancelled;
          job.error_code = ErrorCode::kCancelled;
          job.error_message = "cancelled while running";
        } else if (job.attempts >= max_attempts) {
          job.state = JobState::kFailed;
          job.error_code = ErrorCode::kAborted;
          job.error_message = "the replica running this job stopped " + std::to_string(job.attempts) +
                              " times (crash, kill or out of memory); not run again";
        }
        if (is_final(job.state)) {
          job.end_time_ms = now_ms();
          write_record(txn, job);
          spdlog::info("[{}] lease of replica {} expired: {}", job_tag(job), lost_by, job_state_name(job.state));
          continue;
        }
        spdlog::info("[{}] lease of replica {} expired; taking the job over", job_tag(job), lost_by);
      }
      job.state = JobState::kRunning;
      job.attempts += 1;
      job.start_time_ms = now_ms();
      job.progress = {"starting", 0, 0, 0};
      write_record(txn, job);
      txn.exec_params("UPDATE isocorr_jobs SET claimed_by = $2, lease_until = now() + $3 * interval '1 millisecond', "
                      "cancel_requested = false WHERE id = $1",
                      job.id, replica, static_cast<int64_t>(lease.count()));
      job.version += 1;
      return job;
    }
  });
}

PgJobStore::Renewal PgJobStore::renew(const std::string& id, const std::string& replica,
                                      std::chrono::milliseconds lease, const JobProgressInfo& progress) {
  return database_.transaction([&](pqxx::work& txn) {
    const pqxx::result rows = txn.exec_params(
        "UPDATE isocorr_jobs SET lease_until = now() + $3 * interval '1 millisecond', progress = $4, "
        "version = version + CASE WHEN progress = $4 THEN 0 ELSE 1 END "
        "WHERE id = $1 AND claimed_by = $2 AND state = 'RUNNING' RETURNING cancel_requested",
        id, replica, static_cast<int64_t>(lease.count()), progress_text(progress));
    Renewal renewal;
    renewal.held = !rows.empty();
    renewal.cancel_requested = renewal.held && rows[0][0].as<bool>();
    return renewal;
  });
}

bool PgJobStore::finish(const JobRecord& final_record, const std::string& replica, const EncodedResult* result) {
  return database_.transaction([&](pqxx::work& txn) {
    if (txn.exec_params("SELECT 1 FROM isocorr_jobs WHERE id = $1 AND claimed_by = $2 AND state = 'RUNNING' FOR UPDATE",
                        final_record.id, replica)
            .empty())
      return false;
    if (result) {
      txn.exec_params("DELETE FROM isocorr_results WHERE job_id = $1", final_record.id);
      txn.exec_params("INSERT INTO isocorr_results (job_id, manifest) VALUES ($1, $2)", final_record.id,
                      seal_json(result->manifest));
      for (const auto& [part, bytes] : result->parts)
        txn.exec_params("INSERT INTO isocorr_result_parts (job_id, part, bytes) VALUES ($1, $2, $3)", final_record.id,
                        std::string(result_part_name(part)), pqxx::binarystring(bytes.data(), bytes.size()));
    }
    write_record(txn, final_record);
    return true;
  });
}

void PgJobStore::requeue(const JobRecord& running, const std::string& replica) {
  JobRecord queued = running;
  queued.state = JobState::kQueued;
  queued.attempts -= 1;
  queued.progress = {};
  database_.transaction([&](pqxx::work& txn) {
    if (!txn.exec_params("SELECT 1 FROM isocorr_jobs WHERE id = $1 AND claimed_by = $2 AND state = 'RUNNING' FOR UPDATE",
                         queued.id, replica)
             .empty())
      write_record(txn, queued);
  });
}

void PgJobStore::bind_results_to_their_jobs(pqxx::work& txn) {
  const pqxx::result rows = txn.exec(
      "SELECT r.job_id, r.manifest, j.record FROM isocorr_results r JOIN isocorr_jobs j ON j.id = r.job_id "
      "WHERE r.set_aside IS NULL");
  for (const auto& row : rows) {
    const std::string id = row["job_id"].as<std::string>();
    try {
      json manifest = unseal_json(row["manifest"].as<std::string>());
      if (manifest.contains("job")) continue;
      const JobRecord job = record_from_json(unseal_json(row["record"].as<std::string>()));
      if (job.id != id) throw std::runtime_error("its record names another job");
      bind_manifest(manifest, job);
      txn.exec_params("UPDATE isocorr_results SET manifest = $2 WHERE job_id = $1", id, seal_json(manifest));
      spdlog::info("[job {}] result stored before manifests named their job: bound to its job", id);
    } catch (const pqxx::failure&) {
      throw;
    } catch (const std::exception& e) {  // left unbound: reading it answers DATA_LOSS
      spdlog::error("[job {}] its result cannot be bound to its job: {}", id, e.what());
    }
  }
}

void PgJobStore::result_lost(const std::string& id, const std::string& problem) const {
  database_.transaction([&](pqxx::work& txn) {
    txn.exec_params("UPDATE isocorr_results SET set_aside = $2 WHERE job_id = $1 AND set_aside IS NULL", id, problem);
  });
  throw ServiceError(Kind::kDataLoss, "the result of jobs/" + id + " is corrupted or missing in the shared store (" +
                                          problem + "); run the job again");
}

std::string PgJobStore::read_checked_part(const JobRecord& job, ResultPart part) const {
  const std::string& id = job.id;
  const std::string name(result_part_name(part));
  const pqxx::result rows = database_.transaction([&](pqxx::work& txn) {
    return txn.exec_params(
        "SELECT r.manifest, r.set_aside, p.bytes FROM isocorr_results r "
        "LEFT JOIN isocorr_result_parts p ON p.job_id = r.job_id AND p.part = $2 WHERE r.job_id = $1",
        id, name);
  });
  if (rows.empty()) result_lost(id, "no result stored");
  if (!rows[0]["set_aside"].is_null()) result_lost(id, rows[0]["set_aside"].as<std::string>());
  std::string bytes;
  try {
    const json manifest = unseal_json(rows[0]["manifest"].as<std::string>());
    std::string problem = result_binding_problem(manifest, job);
    if (problem.empty() && !manifest_holds(manifest, part)) throw PartNotStored(id, part);
    if (problem.empty() && rows[0]["bytes"].is_null()) problem = name + " is missing";
    if (problem.empty()) bytes = pqxx::binarystring(rows[0]["bytes"]).str();
    if (problem.empty()) problem = result_part_problem(manifest, part, bytes);
    if (!problem.empty()) result_lost(id, problem);
  } catch (const ServiceError&) {
    throw;
  } catch (const std::exception& e) {
    result_lost(id, std::string("unreadable manifest: ") + e.what());
  }
  return bytes;
}

}  // namespace isocorr::server

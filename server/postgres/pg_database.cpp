#include "postgres/pg_database.h"

#include <spdlog/spdlog.h>

#include "postgres/pg_job_store.h"
#include "service_error.h"

namespace isocorr::server {
using Kind = ServiceError::Kind;

namespace {

constexpr size_t kMaxIdleConnections = 8;
constexpr long kSchemaLockKey = 0x15c022;  // pg_advisory_xact_lock key of schema creation

const char* const kSchema[] = {
    "CREATE TABLE IF NOT EXISTS isocorr_schema (version integer NOT NULL)",
    "CREATE TABLE IF NOT EXISTS isocorr_meshes ("
    " digest text PRIMARY KEY, description text NOT NULL, bytes bytea NOT NULL, set_aside text)",
    "CREATE TABLE IF NOT EXISTS isocorr_jobs ("
    " id text PRIMARY KEY, record text NOT NULL, state text NOT NULL,"
    " source_digest text NOT NULL, target_digest text NOT NULL, create_time_ms bigint NOT NULL,"
    " version bigint NOT NULL DEFAULT 1, progress text NOT NULL DEFAULT '{}',"
    " created_by text, claimed_by text, lease_until timestamptz, cancel_requested boolean NOT NULL DEFAULT false)",
    "CREATE INDEX IF NOT EXISTS isocorr_jobs_by_state ON isocorr_jobs (state, create_time_ms)",
    "CREATE TABLE IF NOT EXISTS isocorr_results ("
    " job_id text PRIMARY KEY REFERENCES isocorr_jobs (id) ON DELETE CASCADE,"
    " manifest text NOT NULL, set_aside text)",
    "CREATE TABLE IF NOT EXISTS isocorr_result_parts ("
    " job_id text NOT NULL REFERENCES isocorr_results (job_id) ON DELETE CASCADE,"
    " part text NOT NULL, bytes bytea NOT NULL, PRIMARY KEY (job_id, part))",
};

}  // namespace

PgDatabase::PgDatabase(std::string url) : url_(std::move(url)) {
  try {
    create_schema();
  } catch (const ServiceError& e) {
    throw std::runtime_error(std::string("cannot use the PostgreSQL store: ") + e.what());
  }
}

void PgDatabase::create_schema() {
  transaction([](pqxx::work& txn) {
    txn.exec_params("SELECT pg_advisory_xact_lock($1)", kSchemaLockKey);
    for (const char* statement : kSchema) txn.exec(statement);
    const pqxx::result versions = txn.exec("SELECT version FROM isocorr_schema");
    if (versions.empty()) {
      txn.exec_params("INSERT INTO isocorr_schema (version) VALUES ($1)", kPgSchemaVersion);
      spdlog::info("store: created the PostgreSQL schema, version {}", kPgSchemaVersion);
    } else if (versions[0][0].as<int>() > kPgSchemaVersion) {
      throw ServiceError(Kind::kFailedPrecondition,
                         "the database holds schema version " + versions[0][0].as<std::string>() +
                             ", newer than this server's " + std::to_string(kPgSchemaVersion));
    } else if (versions[0][0].as<int>() < kPgSchemaVersion) {
      PgJobStore::bind_results_to_their_jobs(txn);  // version 2: manifests name their job
      txn.exec_params("UPDATE isocorr_schema SET version = $1", kPgSchemaVersion);
      spdlog::info("store: upgraded the PostgreSQL schema to version {}", kPgSchemaVersion);
    }
  });
}

std::unique_ptr<pqxx::connection> PgDatabase::borrow() {
  {
    std::lock_guard lock(mutex_);
    if (!idle_.empty()) {
      auto connection = std::move(idle_.back());
      idle_.pop_back();
      return connection;
    }
  }
  return std::make_unique<pqxx::connection>(url_);
}

void PgDatabase::give_back(std::unique_ptr<pqxx::connection> connection) {
  std::lock_guard lock(mutex_);
  if (connection->is_open() && idle_.size() < kMaxIdleConnections) idle_.push_back(std::move(connection));
}

void PgDatabase::run(const std::function<void(pqxx::work&)>& work) {
  std::unique_ptr<pqxx::connection> connection;
  try {
    connection = borrow();
    {
      pqxx::work txn(*connection);
      work(txn);
      txn.commit();
    }
    give_back(std::move(connection));
  } catch (const pqxx::broken_connection& e) {
    // Not given back: the next call opens a new connection.
    spdlog::error("store: PostgreSQL unreachable: {}", e.what());
    throw ServiceError(Kind::kUnavailable, "the shared store (PostgreSQL) cannot be reached; retry later");
  } catch (const pqxx::insufficient_resources& e) {
    if (connection) give_back(std::move(connection));
    spdlog::error("store: PostgreSQL: {}", e.what());
    throw ServiceError(Kind::kResourceExhausted, "the shared store (PostgreSQL) is out of space or memory");
  } catch (const pqxx::failure& e) {
    if (connection) give_back(std::move(connection));
    spdlog::error("store: PostgreSQL: {}", e.what());
    throw std::runtime_error("the shared store (PostgreSQL) failed; the server log has the reason");
  } catch (...) {  // the work's own error: the transaction is rolled back, the connection fine
    if (connection) give_back(std::move(connection));
    throw;
  }
}

}  // namespace isocorr::server

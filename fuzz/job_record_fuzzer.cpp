// A job record (jobs/<id>.json) as the journal reads it back after a crash, a full disk or
// an edit left it in any state: it must come back as a job or be rejected with a
// std::exception, and a record accepted once must survive being written and read again.
#include <cstdint>
#include <exception>
#include <string>

#include <nlohmann/json.hpp>

#include "fuzz_checks.h"
#include "storage/job_record_json.h"
#include "storage/sealed_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The seal (a SHA-256 around the body) is read first; a forged one is rarely right, so
  // the body is also parsed directly below.
  try {
    (void)isocorr::server::unseal_json(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const std::exception&) {
  }
  const nlohmann::json json = nlohmann::json::parse(data, data + size, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded()) return 0;
  isocorr::server::JobRecord job;
  try {
    job = isocorr::server::record_from_json(json);
  } catch (const std::exception&) {
    return 0;  // unreadable: the journal reports it
  }
  const isocorr::server::JobRecord again = isocorr::server::record_from_json(isocorr::server::record_to_json(job));
  ISOCORR_FUZZ_CHECK(again.id == job.id && again.state == job.state && again.create_time_ms == job.create_time_ms);
  return 0;
}

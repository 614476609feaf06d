// Map files as `isocorr eval` reads them: ICMAP1 binary, NumPy .npy or one index per line.
#include <cstdint>
#include <string>

#include "fuzz_checks.h"
#include "isocorr/output/map_files.h"
#include "isocorr/util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
    // A vertex index, or -1 for a vertex without counterpart (a part's reverse map).
    for (int index : isocorr::parse_map(bytes, "fuzz.map")) ISOCORR_FUZZ_CHECK(index >= isocorr::kNoCounterpart);
  } catch (const isocorr::InputError&) {
  }
  return 0;
}

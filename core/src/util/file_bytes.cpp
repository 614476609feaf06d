#include "isocorr/util/file_bytes.h"

#include <fstream>
#include <sstream>

#include "isocorr/util/error.h"

namespace isocorr {

std::string read_file_bytes(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read " + what + " '" + path + "'");
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) throw InputError("cannot read " + what + " '" + path + "': read error");
  return contents.str();
}

void write_file_bytes(const std::string& path, const std::string& bytes, const std::string& what) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw InputError("cannot write " + what + " '" + path + "'");
}

}  // namespace isocorr

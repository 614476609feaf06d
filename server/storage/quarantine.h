// <data-dir>/quarantine/: stored objects found corrupted are moved here rather than deleted,
// for the operator to inspect (quarantine/meshes, quarantine/results, quarantine/jobs). A
// newer copy of the same name replaces an older one. Every move is logged.
#pragma once

#include <filesystem>
#include <string>

namespace isocorr::server {

class Quarantine {
 public:
  explicit Quarantine(const std::filesystem::path& data_dir) : dir_(data_dir / "quarantine") {}

  // Moves a file or directory into quarantine/<kind>/. Never throws: when the move fails
  // (logged), the object is removed instead so that it is not served again.
  void set_aside(const std::string& kind, const std::filesystem::path& path, const std::string& why) const;
  // Copies a file there, leaving the original in place (the caller replaces it).
  void keep_copy(const std::string& kind, const std::filesystem::path& path, const std::string& why) const;
  bool holds(const std::string& kind, const std::string& file_name) const;
  // Renames a copy to a dated name, so that `holds` no longer finds it (the object was
  // repaired) while the operator can still look at it.
  void archive(const std::string& kind, const std::string& file_name) const;

 private:
  std::filesystem::path dir_;
};

}  // namespace isocorr::server

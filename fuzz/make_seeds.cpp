// Writes the generated seed corpus of the fuzz targets: one small, valid input of every
// format and variant each parser knows, so fuzzing starts deep inside the parsers.
// Usage: isocorr-fuzz-seeds <dir>; writes <dir>/<target>/<seed> (fuzz/seeds/ holds the
// hand-written malformed ones).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/procedural_meshes.h"
#include "isocorr/output/map_files.h"
#include "isocorr/settings/settings_json.h"
#include "storage/job_journal.h"

namespace fs = std::filesystem;
using isocorr::TriangleMesh;

namespace {

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string off_text(const TriangleMesh& mesh) {
  std::ostringstream out;
  out << "OFF\n# generated seed\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
  for (const auto& p : mesh.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& f : mesh.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return out.str();
}

// OBJ with the index forms readers meet: v, v/vt, v//vn, v/vt/vn, and a negative index.
std::string obj_text(const TriangleMesh& mesh) {
  std::ostringstream out;
  out << "# generated seed\no blob\n";
  for (const auto& p : mesh.vertices) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  out << "vt 0 0\nvn 0 0 1\n";
  const char* forms[] = {"", "/1", "//1", "/1/1"};
  for (int k = 0; k < mesh.num_faces(); ++k) {
    const auto& f = mesh.faces[k];
    out << 'f';
    for (int v : f) out << ' ' << v + 1 << forms[k % 4];
    out << '\n';
  }
  out << "f -1 -2 -3\n";
  return out.str();
}

std::string ply_ascii_text(const TriangleMesh& mesh) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\ncomment generated seed\nelement vertex " << mesh.num_vertices()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.num_faces()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : mesh.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& f : mesh.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return out.str();
}

fs::path directory(const fs::path& root, const std::string& target) {
  fs::create_directories(root / target);
  return root / target;
}

void write_mesh_seeds(const fs::path& root) {
  const TriangleMesh sphere = isocorr::icosphere(1);  // 42 vertices: enough to be matchable
  const TriangleMesh square = isocorr::grid(2, 2);
  write_text(directory(root, "mesh_off") / "icosphere.off", off_text(sphere));
  write_text(directory(root, "mesh_off") / "square.off", off_text(square));
  write_text(directory(root, "mesh_obj") / "icosphere.obj", obj_text(sphere));
  write_text(directory(root, "mesh_ply") / "icosphere_ascii.ply", ply_ascii_text(sphere));
  isocorr::write_ply((directory(root, "mesh_ply") / "icosphere_binary.ply").string(), sphere);
  std::vector<std::array<unsigned char, 3>> colours(square.vertices.size(), {200, 100, 50});
  isocorr::write_ply((directory(root, "mesh_ply") / "square_colours.ply").string(), square, colours);
}

void write_map_seeds(const fs::path& root) {
  const std::vector<int> map = {0, 2, 1, 7, 3, 65535, 4};
  isocorr::write_map_text((directory(root, "map_file") / "map.txt").string(), map);
  isocorr::write_map_binary((directory(root, "map_file") / "map.bin").string(), map);
  isocorr::write_map_npy((directory(root, "map_file") / "map.npy").string(), map);
}

isocorr::server::JobRecord sample_job() {
  isocorr::server::JobRecord job;
  job.id = "0123456789abcdef";
  job.state = isocorr::server::JobState::kSucceeded;
  job.source_digest = std::string(64, 'a');
  job.target_digest = std::string(64, 'b');
  job.settings.max_tracked = 5;
  job.attempts = 1;
  job.summary.timings = {{"dense", 1.5}};
  job.summary.notes = {"a note"};
  return job;
}

void write_settings_and_record_seeds(const fs::path& root) {
  isocorr::MatchSettings settings;
  write_text(directory(root, "settings_json") / "defaults.json", isocorr::settings_to_json(settings).dump());
  // A journal of its own writes the record exactly as the server does.
  const fs::path journal_dir = root / "journal.tmp";
  isocorr::server::JobJournal journal(journal_dir);
  isocorr::server::JobRecord job = sample_job();
  journal.save(job);
  fs::copy_file(journal_dir / "jobs" / (job.id + ".json"), directory(root, "job_record") / "succeeded.json",
                fs::copy_options::overwrite_existing);
  job.state = isocorr::server::JobState::kFailed;
  job.error_message = "cancelled by the user";
  journal.save(job);
  fs::copy_file(journal_dir / "jobs" / (job.id + ".json"), directory(root, "job_record") / "failed.json",
                fs::copy_options::overwrite_existing);
  fs::remove_all(journal_dir);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <corpus-dir>\n", argv[0]);
    return 2;
  }
  const fs::path root = argv[1];
  write_mesh_seeds(root);
  write_map_seeds(root);
  write_settings_and_record_seeds(root);
  return 0;
}

// isocorr-make-examples DIR: writes the bundled demo pair (the project's own meshes, so
// they may be shipped) as a tiny dataset folder that `isocorr eval` understands:
// DIR/meshes/*.ply, DIR/pairs.tsv and an index-map ground truth. --subdivisions N sets the
// creature's fineness (5, the default, gives 10242 vertices; the CLI tests take 3 and 4:
// 642 and 2562).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <filesystem>
#include <fstream>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/procedural_meshes.h"

int main(int argc, char** argv) {
  const bool help = argc == 2 && std::string(argv[1]) == "--help";
  const bool subdivisions_given = argc == 4 && std::string(argv[2]) == "--subdivisions";
  int subdivisions = 5;
  if (subdivisions_given) {
    char* end = nullptr;
    subdivisions = static_cast<int>(std::strtol(argv[3], &end, 10));
    if (*end != '\0' || subdivisions < 2 || subdivisions > 7) subdivisions = -1;
  }
  if (help || (argc != 2 && !subdivisions_given) || subdivisions < 0) {
    std::fprintf(stderr, "usage: isocorr-make-examples DIR [--subdivisions 2..7]\n");
    return help ? 0 : 2;
  }
  namespace fs = std::filesystem;
  const fs::path dir = argv[1];
  fs::create_directories(dir / "meshes");
  fs::create_directories(dir / "gt");
  const isocorr::TriangleMesh creature = isocorr::limbed_blob(subdivisions);
  const isocorr::RenumberedCopy moved = isocorr::rotated_scaled_renumbered(creature, 1.7, 2024);
  isocorr::write_ply((dir / "meshes/creature.ply").string(), creature);
  isocorr::write_ply((dir / "meshes/creature_moved.ply").string(), moved.mesh);
  std::ofstream truth(dir / "gt/creature_to_moved.txt");
  for (int index : moved.permutation) truth << index << '\n';
  std::ofstream pairs(dir / "pairs.tsv");
  pairs << "source\ttarget\tgt_kind\tprotocol\n"
        << "meshes/creature.ply\tmeshes/creature_moved.ply\tindex_map:gt/creature_to_moved.txt\tdemo\n";
  std::printf("wrote %d-vertex example pair to %s\n", creature.num_vertices(), dir.c_str());
  return 0;
}

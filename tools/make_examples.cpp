// isocorr-make-examples DIR: writes the bundled demo pair (the project's own meshes, so
// they may be shipped) as a tiny dataset folder that `isocorr eval` understands:
// DIR/meshes/*.ply, DIR/pairs.tsv and an index-map ground truth. --subdivisions N sets the
// creature's fineness (5, the default, gives 10242 vertices; the CLI tests take 3 and 4:
// 642 and 2562).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <CLI/CLI.hpp>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/mesh/procedural_meshes.h"

int main(int argc, char** argv) {
  CLI::App app{"Writes the bundled demo pair as a dataset folder that `isocorr eval` understands."};
  std::string out_dir;
  int subdivisions = 5;
  app.add_option("dir", out_dir, "folder to write into")->required();
  app.add_option("--subdivisions", subdivisions, "creature's fineness (5: 10242 vertices)")
      ->check(CLI::Range(2, 7))
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  namespace fs = std::filesystem;
  const fs::path dir = out_dir;
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

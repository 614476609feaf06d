// The meshes-then-map order of the local commands, told from the names alone.
#include "argument_order.h"

#include <string>

#include <gtest/gtest.h>

#include "isocorr/util/error.h"

namespace isocorr::cli {
namespace {

TEST(ArgumentOrder, MeshExtensionsInAnyCase) {
  EXPECT_TRUE(has_mesh_extension("a.off"));
  EXPECT_TRUE(has_mesh_extension("dir.d/b.OBJ"));
  EXPECT_TRUE(has_mesh_extension("/x/c.Ply"));
  EXPECT_FALSE(has_mesh_extension("map.txt"));
  EXPECT_FALSE(has_mesh_extension("map.bin"));
  EXPECT_FALSE(has_mesh_extension("off"));
  EXPECT_FALSE(has_mesh_extension("meshes.off/map"));
}

TEST(ArgumentOrder, MeshesThenMapPass) {
  EXPECT_NO_THROW(check_meshes_before_map("isocorr render SOURCE TARGET MAP", "a.off", "a_to_b.txt"));
  EXPECT_NO_THROW(check_meshes_before_map("isocorr render SOURCE TARGET MAP", "a.ply", "a_to_b.bin"));
  // Names that tell nothing are left to the readers.
  EXPECT_NO_THROW(check_meshes_before_map("isocorr render SOURCE TARGET MAP", "a", "b"));
}

TEST(ArgumentOrder, TheMapFirstIsRefusedNamingTheOrder) {
  try {
    check_meshes_before_map("isocorr render SOURCE TARGET MAP", "a_to_b.txt", "b.off");
    FAIL() << "accepted the map first";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("`isocorr render SOURCE TARGET MAP`"), std::string::npos) << message;
    EXPECT_NE(message.find("'a_to_b.txt' looks like a map and 'b.off' like a mesh"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace isocorr::cli

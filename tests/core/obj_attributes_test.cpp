// OBJ corner attributes: texture coordinates, normals and materials read per triangle
// corner, written back exactly, and every malformed reference an InputError naming its line.
#include "isocorr/mesh/textured_mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "isocorr/mesh/mesh_io.h"
#include "isocorr/util/error.h"

namespace isocorr {
namespace {

using Corners = std::array<int, 3>;

// A square of two triangles and a quad (split into a fan) sharing vertex 2, whose corners
// carry different UVs on either side: a seam. Relative indices, a corner without a UV, a
// corner without a normal, two materials and a face before any usemtl.
const std::string kSeamedObj =
    "mtllib shapes.mtl\n"
    "o seamed\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
    "vt 0 0\nvt 0.5 0\nvt 0.5 0.5\nvt 0 0.5\n"
    "vt 0.75 0.125 0.5\n"  // a third coordinate, dropped
    "vt 0.1\n"             // v defaults to 0
    "vn 0 0 1\nvn 0 0 -1\n"
    "f 1/1/1 2/2/1 3/3/1\n"
    "usemtl skin\n"
    "f 1/1/1 3/3/1 4/4/1\n"
    "usemtl cloth # a comment\n"
    "f 2/5/2 5/6 -1/-2/-1 -4/6/2\n"  // the quad 2 5 6 3: vertex 3 with a second UV
    "usemtl skin\n"
    "f 4//1 3 6\n";

TEST(ObjAttributes, ReadsCornersInTheFaceOrderOfLoadMesh) {
  const TexturedMesh textured = parse_textured_mesh(kSeamedObj, "a.obj");
  const LoadedMesh plain = parse_mesh(kSeamedObj, "a.obj");
  EXPECT_EQ(textured.mesh.vertices, plain.mesh.vertices);
  ASSERT_EQ(textured.mesh.faces, plain.mesh.faces);
  ASSERT_EQ(textured.mesh.num_faces(), 5);

  const CornerAttributes& c = textured.corners;
  EXPECT_EQ(c.material_library, "shapes.mtl");
  ASSERT_EQ(c.uvs.size(), 6u);
  EXPECT_EQ(c.uvs[4], (std::array<double, 2>{0.75, 0.125}));
  EXPECT_EQ(c.uvs[5], (std::array<double, 2>{0.1, 0}));
  ASSERT_EQ(c.normals.size(), 2u);
  EXPECT_EQ(c.normals[1], Vec3(0, 0, -1));
  // The quad's fan: (2 5 6) and (2 6 3); vertex 3 (index 2) has vt 2 in the square, vt 5 here.
  EXPECT_EQ(c.face_uvs, (std::vector<Corners>{{0, 1, 2}, {0, 2, 3}, {4, 5, 4}, {4, 4, 5}, {-1, -1, -1}}));
  EXPECT_EQ(c.face_normals, (std::vector<Corners>{{0, 0, 0}, {0, 0, 0}, {1, -1, 1}, {1, 1, 1}, {0, -1, -1}}));
  EXPECT_EQ(c.materials, (std::vector<std::string>{"skin", "cloth"}));
  EXPECT_EQ(c.face_materials, (std::vector<int>{-1, 0, 1, 1, 0}));
}

void expect_same(const TexturedMesh& a, const TexturedMesh& b) {
  EXPECT_EQ(a.mesh.vertices, b.mesh.vertices);
  EXPECT_EQ(a.mesh.faces, b.mesh.faces);
  EXPECT_EQ(a.corners.uvs, b.corners.uvs);
  EXPECT_EQ(a.corners.face_uvs, b.corners.face_uvs);
  EXPECT_EQ(a.corners.normals, b.corners.normals);
  EXPECT_EQ(a.corners.face_normals, b.corners.face_normals);
  EXPECT_EQ(a.corners.material_library, b.corners.material_library);
  EXPECT_EQ(a.corners.materials, b.corners.materials);
  EXPECT_EQ(a.corners.face_materials, b.corners.face_materials);
}

TEST(ObjAttributes, WriteAndReadBackIsIdentical) {
  TexturedMesh textured = parse_textured_mesh(kSeamedObj, "a.obj");
  // Values whose shortest text is long must come back bit for bit.
  textured.corners.uvs[1] = {1.0 / 3, 2.0 / 3};
  textured.corners.normals[0] = Vec3(0.1, 0.2, 0.7).normalized();
  textured.mesh.vertices[5] = Vec3(2, 1e-300, -7.0 / 9);
  const std::string path = (std::filesystem::temp_directory_path() / "isocorr_obj_attributes.obj").string();
  write_textured_obj(path, textured);
  const TexturedMesh again = load_textured_mesh(path);
  expect_same(again, textured);
  EXPECT_EQ(load_mesh(path).mesh.faces, textured.mesh.faces);
  // And once more: the written text is a fixed point.
  EXPECT_EQ(textured_obj_text(again), textured_obj_text(textured));
  std::filesystem::remove(path);
}

TEST(ObjAttributes, AFileWithoutAttributesHasNone) {
  const TexturedMesh obj = parse_textured_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl unused\n", "a.obj");
  EXPECT_TRUE(obj.corners.face_uvs.empty());
  EXPECT_TRUE(obj.corners.face_normals.empty());
  EXPECT_TRUE(obj.corners.materials.empty() && obj.corners.face_materials.empty());
  const TexturedMesh off = parse_textured_mesh("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "a.obj");
  EXPECT_EQ(off.mesh.num_faces(), 1);
  EXPECT_TRUE(off.corners.uvs.empty() && off.corners.face_uvs.empty());
  // Without attributes the written text is what write_mesh writes.
  EXPECT_EQ(textured_obj_text(obj), "# written by isocorr\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
}

TEST(ObjAttributes, DroppedFanTrianglesTakeTheirCornersWithThem) {
  // The polygon 1 2 2 3 4 repeats a corner: load_mesh keeps (1 2 3) and (1 3 4) only.
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 2 0\nvt 3 0\nvt 4 0\n"
                          "f 1/1 2/2 2/3 3/4 4/5\n";
  const TexturedMesh textured = parse_textured_mesh(obj, "a.obj");
  ASSERT_EQ(textured.mesh.faces, parse_mesh(obj, "a.obj").mesh.faces);
  ASSERT_EQ(textured.mesh.num_faces(), 2);
  EXPECT_EQ(textured.corners.face_uvs, (std::vector<Corners>{{0, 2, 3}, {0, 3, 4}}));
}

TEST(ObjAttributes, MalformedReferencesNameTheirLine) {
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";  // the face is on line 6
  struct Case {
    const char* name;
    std::string text;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"four parts", head + "f 1/1/1/1 2/1/1 3/1/1\n", {"line 6", "'1/1/1/1'", "v/vt/vn"}},
      {"trailing slash", head + "f 1/ 2/ 3/\n", {"line 6", "'1/'"}},
      {"empty normal", head + "f 1// 2// 3//\n", {"line 6", "'1//'"}},
      {"empty normal after vt", head + "f 1/1/ 2/1/ 3/1/\n", {"line 6", "'1/1/'"}},
      {"text index", head + "f 1/a 2/1 3/1\n", {"line 6", "'1/a'", "texture coordinate"}},
      {"index zero", head + "f 1/0 2/1 3/1\n", {"line 6", "'1/0'"}},
      {"vt out of range", head + "f 1/1 2/1 3/7\n", {"line 6", "texture coordinate 7", "has 1"}},
      {"vn out of range", head + "f 1//1 2//2 3//1\n", {"line 6", "normal 2", "has 1"}},
      {"relative vt too far", head + "f 1/-2 2/-1 3/-1\n", {"line 6", "before the first texture coordinate"}},
      {"relative vn too far", head + "f 1//-1 2//-1 3//-3\n", {"line 6", "before the first normal"}},
      {"huge vt", head + "f 1/99999999999 2/1 3/1\n", {"line 6", "out of range"}},
      {"vt NaN", "vt 0 nan\n" + head + "f 1 2 3\n", {"line 1", "texture coordinate"}},
      {"vt empty", "vt\n" + head + "f 1 2 3\n", {"line 1", "texture coordinate"}},
      {"vt word", "vt zero\n" + head + "f 1 2 3\n", {"line 1", "texture coordinate"}},
      {"vn short", head + "vn 0 1\nf 1 2 3\n", {"line 6", "normal needs three"}},
      {"vn inf", head + "vn 0 1 inf\nf 1 2 3\n", {"line 6", "normal"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    try {
      parse_textured_mesh(c.text, "a.obj");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      for (const std::string& part : c.expected) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  }
}

TEST(ObjAttributes, ForwardReferencesAreCheckedAtTheEnd) {
  // A face may name a vt defined below it, as it may a vertex.
  const std::string obj = "f 1/1 2/2 3/1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n";
  EXPECT_EQ(parse_textured_mesh(obj, "a.obj").corners.face_uvs, (std::vector<Corners>{{0, 1, 0}}));
}

TEST(ObjAttributes, MatchingStillReadsFilesWithBrokenAttributes) {
  // parse_mesh needs only positions, and reads what it always has.
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/9 2/x/y 3//\n";
  EXPECT_EQ(parse_mesh(obj, "a.obj").mesh.num_faces(), 1);
  EXPECT_THROW(parse_textured_mesh(obj, "a.obj"), InputError);
}

TEST(ObjAttributes, AttributesThatDoNotFitTheMeshAreNotWritten) {
  TexturedMesh textured = parse_textured_mesh(kSeamedObj, "a.obj");
  textured.corners.face_uvs.pop_back();
  EXPECT_THROW(textured_obj_text(textured), InputError);
  textured = parse_textured_mesh(kSeamedObj, "a.obj");
  textured.corners.face_normals[0][1] = 2;
  EXPECT_THROW(check_corner_attributes(textured.mesh, textured.corners), InputError);
  textured = parse_textured_mesh(kSeamedObj, "a.obj");
  textured.corners.face_materials[0] = 5;
  EXPECT_THROW(check_corner_attributes(textured.mesh, textured.corners), InputError);
}

}  // namespace
}  // namespace isocorr

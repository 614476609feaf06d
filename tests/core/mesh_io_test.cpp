// Mesh readers and writers: every supported dialect, and every malformed input
// becoming an InputError that names the problem.
#include "isocorr/mesh/mesh_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "isocorr/util/error.h"

#ifndef ISOCORR_SHARED_DATA_DIR
#define ISOCORR_SHARED_DATA_DIR "../shared/data"
#endif

namespace isocorr {
namespace {

// An outward-oriented tetrahedron, as the text formats below spell it.
const std::vector<Vec3> kTetraVertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::vector<Face> kTetraFaces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

const std::string kTetraOff =
    "OFF\n"
    "# a tetrahedron\n"
    "4 4 6\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
    "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

void expect_tetrahedron(const TriangleMesh& mesh) {
  ASSERT_EQ(mesh.num_vertices(), 4);
  ASSERT_EQ(mesh.num_faces(), 4);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(mesh.vertices[v], kTetraVertices[v]) << "vertex " << v;
  EXPECT_EQ(mesh.faces, kTetraFaces);
}

// Binary PLY pieces; the tests assume a little-endian host, as every supported platform is.
template <class T>
void put(std::string& out, T value, bool big_endian = false) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (big_endian) std::reverse(raw, raw + sizeof(T));
  out.append(raw, sizeof(T));
}

// Tetrahedron with double coordinates, an extra uchar and a leading element with a list.
std::string binary_tetra_ply(bool big_endian, std::uint32_t vertex_count = 4) {
  std::string ply = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment made by hand\n"
                    "element material 2\nproperty list uchar float coefficients\nproperty int id\n"
                    "element vertex " + std::to_string(vertex_count) + "\n"
                    "property float64 x\nproperty double y\nproperty double z\nproperty uchar red\n"
                    "element face 4\nproperty uchar flags\nproperty list uint8 int32 vertex_index\n"
                    "end_header\n";
  put<std::uint8_t>(ply, 2);
  put<float>(ply, 0.5f, big_endian), put<float>(ply, 0.25f, big_endian), put<int>(ply, 7, big_endian);
  put<std::uint8_t>(ply, 0);
  put<int>(ply, 8, big_endian);
  for (const Vec3& p : kTetraVertices) {
    for (int axis = 0; axis < 3; ++axis) put<double>(ply, p[axis], big_endian);
    put<std::uint8_t>(ply, 200);
  }
  for (const Face& f : kTetraFaces) {
    put<std::uint8_t>(ply, 1);
    put<std::uint8_t>(ply, 3);
    for (int v : f) put<int>(ply, v, big_endian);
  }
  return ply;
}

const std::string kTetraAsciiPly =
    "ply\r\nformat ascii 1.0\r\n"
    "element vertex 4\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
    "property float nx\r\nproperty list uchar int extra\r\n"
    "element face 4\r\nproperty list uchar uint vertex_indices\r\nproperty uchar red\r\n"
    "element edge 1\r\nproperty int vertex1\r\nproperty int vertex2\r\n"
    "end_header\r\n"
    "0 0 0 1 0\r\n1 0 0 1 2 5 6\r\n0 1 0 1 0\r\n0 0 1 1 1 9\r\n"
    "3 0 2 1 10\r\n3 0 1 3 20\r\n3 0 3 2 30\r\n3 1 2 3 40\r\n"
    "0 1\r\n";

std::string message_of(const std::string& bytes, const std::string& hint) {
  try {
    parse_mesh(bytes, hint);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MeshIo, ReadsOffTetrahedron) {
  const LoadedMesh loaded = parse_mesh(kTetraOff, "");
  EXPECT_EQ(loaded.format, "off");
  EXPECT_TRUE(loaded.notes.empty());
  expect_tetrahedron(loaded.mesh);
}

TEST(MeshIo, ReadsOffWithCountsOnHeaderLineCrlfAndComments) {
  const std::string off =
      "OFF 4 4 0 # counts on the keyword line\r\n\r\n0 0 0\r\n1 0 0 # first\r\n0 1 0\r\n+0 0 1e0\r\n"
      "3 0 2 1\r\n3 0 1 3\r\n3 0 3 2\r\n3 1 2 3";
  expect_tetrahedron(parse_mesh(off, "x.off").mesh);
}

TEST(MeshIo, ReadsNoffWithNormalsAndCoffWithColours) {
  const std::string noff =
      "NOFF\n4 4 6\n0 0 0 -1 -1 -1\n1 0 0 1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  expect_tetrahedron(parse_mesh(noff, "").mesh);
  const std::string cnoff =
      "CNOFF\n4 4 6\n0 0 0 0 0 1 255 0 0 255\n1 0 0 0 0 1 0.5 0.5 0.5 1\n0 1 0 0 0 1 1 1 1 1\n0 0 1 0 0 1 0 0 0 1\n"
      "3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3 0.1 0.2 0.3 1\n";
  expect_tetrahedron(parse_mesh(cnoff, "").mesh);
}

TEST(MeshIo, TriangulatesQuadsAndSaysSo) {
  const std::string quads =
      "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n4 1 4 2 3\n";
  const LoadedMesh loaded = parse_mesh(quads, "");
  ASSERT_EQ(loaded.mesh.num_faces(), 4);
  EXPECT_EQ(loaded.mesh.faces[0], (Face{0, 1, 2}));
  EXPECT_EQ(loaded.mesh.faces[1], (Face{0, 2, 3}));
  ASSERT_EQ(loaded.notes.size(), 1u);
  EXPECT_NE(loaded.notes[0].find("split 2 polygons"), std::string::npos) << loaded.notes[0];
}

TEST(MeshIo, ReadsObjWithSlashFormsAndRelativeIndices) {
  const std::string obj =
      "# tetrahedron\nmtllib none.mtl\no tetra\n"
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1 1.0\n"
      "vt 0 0\nvn 0 0 1\ns off\n"
      "f 1 3 2\nf 1/1 2/1 4/1\nf 1//1 4//1 3//1\nf -3/1/1 -2/1/1 -1/1/1\n";
  const LoadedMesh loaded = parse_mesh(obj, "tetra.OBJ");
  EXPECT_EQ(loaded.format, "obj");
  expect_tetrahedron(loaded.mesh);
}

TEST(MeshIo, ReadsAsciiPlyWithExtraPropertiesAndElements) {
  const LoadedMesh loaded = parse_mesh(kTetraAsciiPly, "");
  EXPECT_EQ(loaded.format, "ply-ascii");
  expect_tetrahedron(loaded.mesh);
}

TEST(MeshIo, ReadsBinaryPlyInBothByteOrders) {
  const LoadedMesh little = parse_mesh(binary_tetra_ply(false), "");
  EXPECT_EQ(little.format, "ply-binary-le");
  expect_tetrahedron(little.mesh);
  const LoadedMesh big = parse_mesh(binary_tetra_ply(true), "");
  EXPECT_EQ(big.format, "ply-binary-be");
  expect_tetrahedron(big.mesh);
}

TEST(MeshIo, PicksFormatByExtensionWhenContentIsSilent) {
  EXPECT_EQ(parse_mesh("# comment first\n" + kTetraOff, "shape.Off").format, "off");
  EXPECT_NE(message_of("hello world\n", "shape.xyz").find("format"), std::string::npos);
}

TEST(MeshIo, WritePlyRoundTrips) {
  TriangleMesh mesh{{{0, 0, 0}, {1.5, 0, 0}, {0, -2.25, 0}, {0, 0, 1e3}}, kTetraFaces};
  const std::string plain = testing::TempDir() + "/isocorr_round_trip.ply";
  const std::string coloured = testing::TempDir() + "/isocorr_round_trip_colours.ply";
  write_ply(plain, mesh);
  write_ply(coloured, mesh, {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {9, 9, 9}});
  for (const std::string& path : {plain, coloured}) {
    const LoadedMesh loaded = load_mesh(path);
    EXPECT_EQ(loaded.format, "ply-binary-le");
    ASSERT_EQ(loaded.mesh.num_vertices(), 4);
    for (int v = 0; v < 4; ++v) EXPECT_EQ(loaded.mesh.vertices[v], mesh.vertices[v]);
    EXPECT_EQ(loaded.mesh.faces, mesh.faces);
    std::filesystem::remove(path);
  }
}

// OFF and OBJ keep every coordinate exactly (the shortest text of each double), PLY as float.
TEST(MeshIo, WriteMeshRoundTripsByExtension) {
  TriangleMesh mesh{{{0.1, 1.0 / 3, -2.25}, {1e-300, 0, 7}, {0, -2.25e17, 0}, {0.7, 0.2, 1e3}}, kTetraFaces};
  for (const std::string name : {"exact.off", "exact.OBJ", "float.ply"}) {
    const std::string path = testing::TempDir() + "/isocorr_write_mesh_" + name;
    write_mesh(path, mesh);
    const LoadedMesh loaded = load_mesh(path);
    ASSERT_EQ(loaded.mesh.num_vertices(), 4) << name;
    EXPECT_EQ(loaded.mesh.faces, mesh.faces) << name;
    for (int v = 0; v < 4; ++v)
      for (int axis = 0; axis < 3; ++axis) {
        const double expected = name == "float.ply" ? static_cast<float>(mesh.vertices[v][axis]) : mesh.vertices[v][axis];
        EXPECT_EQ(loaded.mesh.vertices[v][axis], expected) << name << " vertex " << v;
      }
    std::filesystem::remove(path);
  }
  try {
    write_mesh(testing::TempDir() + "/isocorr_write_mesh.stl", mesh);
    ADD_FAILURE() << "wrote an .stl";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("must end in .off, .obj or .ply"), std::string::npos) << e.what();
  }
}

TEST(MeshIo, LoadMeshNamesUnreadablePath) {
  const std::string path = "/nonexistent/dir/missing_mesh.off";
  try {
    load_mesh(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

struct BadInput {
  const char* name;
  std::string bytes;
  std::string hint;
  std::vector<std::string> words;  // each must appear in the message
};

std::vector<BadInput> bad_inputs() {
  const std::string off_head = "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string pad = "# padding that gets short bodies past the header size check\n";
  const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  auto le_header = [](const std::string& elements) {
    return "ply\nformat binary_little_endian 1.0\n" + elements + "end_header\n";
  };
  std::string huge_list = le_header("element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                    "element face 1\nproperty list int int vertex_indices\n");
  for (int i = 0; i < 9; ++i) put<float>(huge_list, 0.0f);
  put<int>(huge_list, 2000000000);
  put<int>(huge_list, 0);
  std::string nan_ply = le_header("element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                  "element face 1\nproperty list uchar int vertex_indices\n");
  for (int i = 0; i < 9; ++i) put<float>(nan_ply, i == 4 ? std::numeric_limits<float>::quiet_NaN() : 0.0f);
  put<std::uint8_t>(nan_ply, 3), put<int>(nan_ply, 0), put<int>(nan_ply, 1), put<int>(nan_ply, 2);
  const std::string binary = binary_tetra_ply(false);

  return {
      {"empty", "", "a.off", {"empty"}},
      {"whitespace only", " \n\t\n", "a.ply", {"empty"}},
      {"four bytes of OFF", "OFF\n", "", {"counts"}},
      {"four bytes of garbage", std::string("\x01\x02\x03\x04", 4), "a.ply", {"ply"}},
      {"four bytes, unknown", "abcd", "", {"format"}},
      {"huge OFF counts", "OFF\n2000000000 2000000000 0\n0 0 0\n", "", {"2000000000", "bytes"}},
      {"negative OFF counts", "OFF\n-4 4 6\n", "", {"negative"}},
      {"non-numeric OFF counts", "OFF\nfour four six\n", "", {"counts"}},
      {"binary OFF", "OFF BINARY\n", "", {"binary"}},
      {"4OFF", "4OFF\n4 4 6\n", "", {"4OFF"}},
      {"OFF truncated in vertices", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n" + pad, "", {"truncated", "3 of 4 vertices"}},
      {"OFF truncated in faces", off_head + "3 0 2 1\n3 0 1 3\n3 0 3 2\n" + pad, "", {"truncated", "3 of 4 faces"}},
      {"OFF face cut short", off_head + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2\n", "", {"face 3", "2 of its 3"}},
      {"OFF missing coordinate", "OFF\n4 1 0\n0 0 0\n1 0\n0 1 0\n0 0 1\n3 0 1 2\n" + pad, "", {"vertex 1", "line 4"}},
      {"OFF NaN", "OFF\n4 1 0\n0 0 0\n1 nan 0\n0 1 0\n0 0 1\n3 0 1 2\n", "", {"vertex 1", "non-finite"}},
      {"OFF inf", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 -inf\n0 0 1\n3 0 1 2\n", "", {"vertex 2", "non-finite"}},
      {"OFF overflow", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 1e999\n0 0 1\n3 0 1 2\n", "", {"vertex 2", "non-finite"}},
      {"OFF index out of range", off_head + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 9001\n", "",
       {"face 3 refers to vertex 9001 but the file has 4 vertices"}},
      {"OFF huge index", off_head + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 99999999999\n", "", {"face 3", "99999999999"}},
      {"OFF negative index", off_head + "3 0 2 1\n3 0 -1 3\n3 0 3 2\n3 1 2 3\n", "", {"face 1", "negative"}},
      {"OFF non-integer index", off_head + "3 0 2 1\n3 0 1.5 3\n3 0 3 2\n3 1 2 3\n", "", {"face 1", "'1.5'"}},
      {"OFF two-corner face", off_head + "3 0 2 1\n2 0 1\n3 0 3 2\n3 1 2 3\n", "", {"face 1", "at least 3"}},
      {"OFF huge corner count", off_head + "2000000000 0 1 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "", {"face 0", "corners"}},
      {"OFF zero faces", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "", {"no faces"}},
      {"OBJ zero faces", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "a.obj", {"no faces"}},
      {"OBJ index zero", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "a.obj", {"line 4", "'0'"}},
      {"OBJ relative too far", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "a.obj", {"line 4", "before the first vertex"}},
      {"OBJ out of range", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "a.obj",
       {"line 4 refers to vertex 9 but the file has 3 vertices"}},
      {"OBJ two corners", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "a.obj", {"line 4", "at least 3"}},
      {"OBJ NaN", "v 0 0 0\nv 1 NaN 0\nv 0 1 0\nf 1 2 3\n", "a.obj", {"line 2", "non-finite"}},
      {"OBJ short vertex", "v 0 0\nf 1 1 1\n", "a.obj", {"line 1", "three"}},
      {"PLY huge ASCII count", "ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                               "0 0 0\n3 0 0 0\n", "", {"2000000000", "vertex"}},
      {"PLY huge binary count", binary_tetra_ply(false, 2000000000u), "", {"2000000000", "vertex"}},
      {"PLY negative count", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "", {"element 'vertex'", "non-negative"}},
      {"PLY truncated binary", binary.substr(0, binary.size() - 5), "", {"face 3", "truncated"}},
      {"PLY truncated ASCII", ply_head + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "", {"face 0", "truncated"}},
      {"PLY no end_header", "ply\nformat ascii 1.0\nelement vertex 3\n", "", {"end_header"}},
      {"PLY no format", "ply\nelement vertex 0\nend_header\n", "", {"format"}},
      {"PLY unknown type", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n", "", {"float128"}},
      {"PLY unknown keyword", "ply\nformat ascii 1.0\nbogus\nend_header\n", "", {"bogus"}},
      {"PLY property before element", "ply\nformat ascii 1.0\nproperty float x\nend_header\n", "", {"before any element"}},
      {"PLY missing z", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n3 0 0 0\n", "", {"'z'"}},
      {"PLY no faces", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                       "end_header\n0 0 0\n", "", {"no faces"}},
      {"PLY face without index list", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                      "property float z\nelement face 1\nproperty int foo\nend_header\n0 0 0\n1\n",
       "", {"vertex_indices"}},
      {"PLY huge list", huge_list, "", {"face 0", "truncated"}},
      {"PLY NaN", nan_ply, "", {"vertex 1", "non-finite"}},
      {"PLY index out of range", ply_head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", "",
       {"face 0 refers to vertex 7 but the file has 3 vertices"}},
      {"PLY negative index", ply_head + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "", {"face 0", "negative"}},
      {"PLY fractional index", ply_head + "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", "", {"face 0", "not an integer"}},
      {"PLY two corners", ply_head + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "", {"face 0", "at least 3"}},
      {"PLY word for number", ply_head + "0 zero 0\n1 0 0\n0 1 0\n3 0 1 2\n", "", {"vertex 0", "'zero'"}},
  };
}

TEST(MeshIo, RejectsEveryBadInputWithAMessage) {
  for (const BadInput& bad : bad_inputs()) {
    SCOPED_TRACE(bad.name);
    EXPECT_THROW(parse_mesh(bad.bytes, bad.hint), InputError);
    const std::string message = message_of(bad.bytes, bad.hint);
    for (const std::string& word : bad.words) EXPECT_NE(message.find(word), std::string::npos) << message;
  }
}

// Every prefix and many random corruptions of valid files must parse or raise InputError:
// no other exception, no crash, no hang.
TEST(MeshIo, SurvivesTruncationAndCorruption) {
  const std::vector<std::pair<std::string, std::string>> samples = {
      {kTetraOff, "a.off"}, {kTetraAsciiPly, "a.ply"}, {binary_tetra_ply(false), "a.ply"},
      {binary_tetra_ply(true), "a.ply"}, {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf -1 -2 -3\n", "a.obj"}};
  std::mt19937 random(12345);
  auto survives = [](const std::string& bytes, const std::string& hint) {
    try {
      parse_mesh(bytes, hint);
    } catch (const InputError&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << "unexpected exception: " << e.what();
    }
  };
  for (const auto& [bytes, hint] : samples) {
    for (size_t length = 0; length < bytes.size(); ++length) survives(bytes.substr(0, length), hint);
    for (int trial = 0; trial < 400; ++trial) {
      std::string corrupt = bytes;
      for (int flips = 1 + trial % 4; flips > 0; --flips)
        corrupt[random() % corrupt.size()] = static_cast<char>(random() % 256);
      survives(corrupt, hint);
    }
  }
}

TEST(MeshIo, LoadsRealOffFileFromSharedData) {
  const std::string path = std::string(ISOCORR_SHARED_DATA_DIR) + "/tosca_hires/off/wolf0.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found at " << path;
  const LoadedMesh loaded = load_mesh(path);
  EXPECT_EQ(loaded.format, "off");
  EXPECT_EQ(loaded.mesh.num_vertices(), 4344);
  EXPECT_EQ(loaded.mesh.num_faces(), 8684);
}

}  // namespace
}  // namespace isocorr

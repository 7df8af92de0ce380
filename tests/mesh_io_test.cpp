// OBJ and PLY parsing: what the files mean, and every refusal verbatim.
#include <cstring>

#include "layerlab/framework/error.h"
#include "layerlab/targets/mesh_io.h"
#include "layerlab/tests/render_test_util.h"

namespace layerlab {
namespace {

using Tri = std::array<uint32_t, 3>;

std::string ObjError(const std::string& text, const MeshLimits& limits = {}) {
  try {
    ParseObj(text, "m.obj", limits);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string PlyError(const std::string& bytes) {
  try {
    ParsePly(bytes, "m.ply");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ObjTest, FanTriangulatesPolygonsAndResolvesNegativeIndices) {
  TriangleMesh m = ParseObj(
      "# a pentagon, then a triangle by relative indices\n"
      "o shape\ng part\ns off\nusemtl none\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0 1\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0.5 1\nvt 0 1\n"
      "vn 0 0 1\n"
      "f 1/1/1 2/2/1 3/3/1 4/4/1 5/5/1\n"
      "f -5/-5 -4/-4 -1/-1\n",
      "m.obj");
  ASSERT_EQ(m.positions.size(), 5u);
  EXPECT_EQ(m.positions[3], (std::array<double, 3>{0.5, 1.5, 0}));
  ASSERT_EQ(m.triangles.size(), 4u);
  EXPECT_EQ(m.triangles[0], (Tri{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Tri{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (Tri{0, 3, 4}));
  EXPECT_EQ(m.triangles[3], (Tri{0, 1, 4}));
  ASSERT_TRUE(m.has_uvs());
  EXPECT_EQ(m.triangle_uvs, m.triangles);
  EXPECT_EQ(m.uvs[3], (std::array<double, 2>{0.5, 1}));
}

TEST(ObjTest, TextureIndicesAreIndependentOfVertexIndices) {
  TriangleMesh m =
      ParseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 0.25 0\nvt 0.5 0\nvn 0 0 1\nf 1/3 2/1/1 3/2\n", "m.obj");
  EXPECT_EQ(m.triangles[0], (Tri{0, 1, 2}));
  EXPECT_EQ(m.triangle_uvs[0], (Tri{2, 0, 1}));
}

TEST(ObjTest, VertexNormalFormHasNoTextureCoordinates) {
  TriangleMesh m = ParseObj("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nvn 0 0 1\r\nf 1//1 2//1 3//1 # comment\r\n", "m.obj");
  EXPECT_EQ(m.triangles.size(), 1u);
  EXPECT_FALSE(m.has_uvs());
}

const char* kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(ObjTest, RefusesBadInputNamingFileAndLine) {
  std::string t = kTriangle;
  EXPECT_EQ(ObjError("v 0 0 0\nv nan 0 0\n"), "m.obj:2: vertex coordinate \"nan\" is not a finite number");
  EXPECT_EQ(ObjError("v 0 0 inf\n"), "m.obj:1: vertex coordinate \"inf\" is not a finite number");
  EXPECT_EQ(ObjError("v 0 0 1e999\n"), "m.obj:1: vertex coordinate \"1e999\" is not a number");
  EXPECT_EQ(ObjError("v 0 0\n"), "m.obj:1: a vertex needs 3 coordinates (x y z), got 2 values");
  EXPECT_EQ(ObjError("v 0 zero 0\n"), "m.obj:1: vertex coordinate \"zero\" is not a number");
  EXPECT_EQ(ObjError(t + "f 1 2 4\n"), "m.obj:4: vertex index 4 is out of range (3 vertices defined so far)");
  EXPECT_EQ(ObjError(t + "f 1 2 -4\n"), "m.obj:4: vertex index -4 is out of range (3 vertices defined so far)");
  EXPECT_EQ(ObjError(t + "f 0 1 2\n"), "m.obj:4: vertex index 0 is invalid; OBJ indices start at 1");
  EXPECT_EQ(ObjError(t + "f 1 2 x\n"), "m.obj:4: vertex index \"x\" is not an integer");
  EXPECT_EQ(ObjError(t + "f 1 2\n"), "m.obj:4: a face needs at least 3 vertices, got 2");
  EXPECT_EQ(ObjError(t + "f 1/ 2 3\n"), "m.obj:4: \"1/\" is not a face vertex (expected i, i/t, i/t/n or i//n)");
  EXPECT_EQ(ObjError(t + "vt 0 0\nf 1/2 2/1 3/1\n"),
            "m.obj:5: texture coordinate index 2 is out of range (1 texture coordinate defined so far)");
  EXPECT_EQ(ObjError(t + "vn 0 0 1\nf 1//2 2//1 3//1\n"),
            "m.obj:5: normal index 2 is out of range (1 normal defined so far)");
  EXPECT_EQ(ObjError(t + "vt 0 0\nf 1/1 2 3\n"),
            "m.obj:5: the face mixes vertices with and without texture coordinates");
  EXPECT_EQ(ObjError(t + "vt 0 0\nf 1/1 2/1 3/1\nf 1 2 3\n"),
            "m.obj:6: the face has no texture coordinates, but the faces above it do");
  EXPECT_EQ(ObjError("curv 0 1 1 2\n"),
            "m.obj:1: unsupported statement \"curv\" (this reader takes v, vt, vn and f; o, g, s, mtllib, usemtl, p "
            "and l are ignored)");
  EXPECT_EQ(ObjError(t), "m.obj: the file has no faces");
  MeshLimits small;
  small.max_vertices = 2;
  EXPECT_EQ(ObjError(t, small), "m.obj:3: more than 2 vertices");
  small = {};
  small.max_polygon_vertices = 3;
  EXPECT_EQ(ObjError(t + "v 1 1 0\nf 1 2 3 4\n", small), "m.obj:5: a face of 4 vertices; the limit is 3");
}

const char* kAsciiPly =
    "ply\n"
    "format ascii 1.0\n"
    "comment a unit square with texture coordinates, and an element to skip\n"
    "element vertex 4\n"
    "property float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty float s\nproperty float t\n"
    "element face 1\n"
    "property list uchar int vertex_indices\n"
    "element edge 1\n"
    "property int vertex1\nproperty int vertex2\n"
    "end_header\n"
    "0 0 1 255 0 0\n1 0 1 255 1 0\n1 1 1 255 1 1\n0 1 1 255 0 1\n"
    "4 0 1 2 3\n"
    "0 1\n";

TEST(PlyTest, ReadsAsciiWithTextureCoordinatesAndSkipsOtherElements) {
  TriangleMesh m = ParsePly(kAsciiPly, "m.ply");
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[2], (std::array<double, 3>{1, 1, 1}));
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[0], (Tri{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Tri{0, 2, 3}));
  ASSERT_TRUE(m.has_uvs());
  EXPECT_EQ(m.uvs[2], (std::array<double, 2>{1, 1}));
}

template <class T>
void Put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // this test runs on little-endian machines
  out.append(bytes, sizeof(T));
}

std::string BinaryPly(int faces_declared, bool truncate) {
  std::string out =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nproperty short flags\nelement face " +
      std::to_string(faces_declared) + "\nproperty list uchar uint vertex_indices\nend_header\n";
  const double v[3][3] = {{0.125, -2.5, 3}, {1e-3, 2, 4}, {7, 8, 9}};
  for (auto& p : v) {
    for (double c : p) Put(out, c);
    Put<int16_t>(out, -1);
  }
  Put<uint8_t>(out, 3);
  for (uint32_t i : {2u, 1u, 0u}) Put(out, i);
  if (truncate) out.resize(out.size() - 2);
  return out;
}

TEST(PlyTest, ReadsBinaryLittleEndianExactly) {
  TriangleMesh m = ParsePly(BinaryPly(1, false), "m.ply");
  ASSERT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.positions[0], (std::array<double, 3>{0.125, -2.5, 3}));
  EXPECT_EQ(m.positions[1], (std::array<double, 3>{1e-3, 2, 4}));
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], (Tri{2, 1, 0}));
  EXPECT_FALSE(m.has_uvs());
}

TEST(PlyTest, RefusesBadInputNamingTheElement) {
  EXPECT_EQ(PlyError("solid\n"), "m.ply: not a PLY file (the first line is not \"ply\")");
  EXPECT_EQ(
      PlyError("ply\nformat binary_big_endian 1.0\nend_header\n"),
      "m.ply: header line 2: binary_big_endian PLY is not supported; convert it to binary_little_endian or ascii");
  EXPECT_EQ(PlyError("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"),
            "m.ply: the PLY header has no end_header line");
  EXPECT_EQ(PlyError("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n"),
            "m.ply: header line 4: unknown property type \"quad\"");
  EXPECT_EQ(PlyError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0\n3 0 0 0\n"),
            "m.ply: the vertex element has no scalar property z");
  std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  EXPECT_EQ(PlyError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 7\n"),
            "m.ply: face 1: vertex index 7 is out of range (3 vertices)");
  EXPECT_EQ(PlyError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 -1\n"),
            "m.ply: face 1: vertex index -1 is out of range (3 vertices)");
  EXPECT_EQ(PlyError(header + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n"),
            "m.ply: vertex 1: property x is NaN; coordinates must be finite");
  EXPECT_EQ(PlyError(header + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n3 0 1 2\n"),
            "m.ply: face 0: a face needs at least 3 vertices, got 2");
  EXPECT_EQ(PlyError(header + "0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n3 0 1 2\n"), "m.ply: face 0: \"1.5\" is not an integer");
  EXPECT_EQ(PlyError(BinaryPly(1, true)), "m.ply: face 0: the file ends early");
  EXPECT_EQ(PlyError(BinaryPly(100, false)),
            "m.ply: the header declares more data than the file holds (178 bytes at least, 91 bytes left)");
  EXPECT_EQ(PlyError("ply\nformat ascii 1.0\nelement vertex 99999999999\nend_header\n"),
            "m.ply: header line 3: 99999999999 vertex elements; the limit is 16777216");
}

TEST(MeshFileTest, ReadsByExtensionAndNamesMissingFiles) {
  std::string dir = testing::ScratchDir();
  std::string obj = testing::WriteTextFile(dir + "/tri.OBJ", std::string(kTriangle) + "f 1 2 3\n");
  EXPECT_EQ(ReadMesh(obj).triangles.size(), 1u);
  std::string ply = testing::WriteTextFile(dir + "/square.ply", kAsciiPly);
  EXPECT_EQ(ReadMesh(ply).triangles.size(), 2u);
  try {
    ReadMesh(dir + "/mesh.stl");
    FAIL() << "an STL file was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/mesh.stl: unknown mesh format \".stl\"; expected .obj or .ply");
  }
  try {
    ReadMesh(dir + "/missing.obj");
    FAIL() << "a missing file was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/missing.obj: cannot read: No such file or directory");
  }
}

}  // namespace
}  // namespace layerlab

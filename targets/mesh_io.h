// Triangle meshes from OBJ and PLY files, in the file's own units (the
// target scene scales and places them). Polygons are fan-triangulated.
//
// OBJ: `v x y z [w]` (w ignored; `v x y z r g b` vertex colors also ignored),
// `vt u [v [w]]`, `vn` (only checked as an index target), `f` with 1-based or
// negative (relative) indices in the forms i, i/t, i/t/n and i//n. A face may
// only use vertices defined above it. Grouping and material statements (o, g,
// s, mtllib, usemtl) and points and lines (p, l) are ignored; anything else,
// such as free-form curves, is refused. Either every face has texture
// coordinates or none does. Errors read "die.obj:12: ...".
//
// PLY: ascii or binary_little_endian 1.0; element `vertex` with properties
// x, y, z and optional u, v (or s, t, or texture_u, texture_v); element `face`
// with a list property vertex_indices (or vertex_index). Other elements and
// properties are skipped. Errors read "die.ply: face 12: ..." or
// "die.ply: header line 3: ...".
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace layerlab {

struct TriangleMesh {
  std::vector<std::array<double, 3>> positions;
  std::vector<std::array<uint32_t, 3>> triangles;  // indices into positions
  // Texture coordinates: either both empty, or one uv triple per triangle.
  std::vector<std::array<double, 2>> uvs;
  std::vector<std::array<uint32_t, 3>> triangle_uvs;  // indices into uvs

  bool has_uvs() const { return !triangle_uvs.empty(); }
};

struct MeshLimits {
  size_t max_bytes = size_t{1} << 30;
  size_t max_vertices = size_t{1} << 24;
  size_t max_triangles = size_t{1} << 24;
  size_t max_polygon_vertices = 256;
};

// By extension: .obj or .ply (any case). Throws layerlab::Error naming the file.
TriangleMesh ReadMesh(const std::string& path, const MeshLimits& limits = {});

// The parsers on file contents; `file` names the source in messages.
TriangleMesh ParseObj(const std::string& text, const std::string& file, const MeshLimits& limits = {});
TriangleMesh ParsePly(const std::string& bytes, const std::string& file, const MeshLimits& limits = {});

}  // namespace layerlab

#include "layerlab/targets/mesh_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

std::optional<double> ParseDouble(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double value = 0;
  auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return value;
}

std::optional<long long> ParseInteger(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  long long value = 0;
  auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size()) return std::nullopt;
  return value;
}

// "12" for integral values, "1.5" otherwise.
std::string FormatCount(double value) {
  if (value == std::floor(value) && std::abs(value) < 1e15) return std::to_string(static_cast<long long>(value));
  std::ostringstream out;
  out << value;
  return out.str();
}

void FanTriangulate(const std::vector<uint32_t>& polygon, std::vector<std::array<uint32_t, 3>>& out) {
  for (size_t k = 1; k + 1 < polygon.size(); ++k) out.push_back({polygon[0], polygon[k], polygon[k + 1]});
}

// ---- OBJ ------------------------------------------------------------------

class ObjParser {
 public:
  ObjParser(const std::string& file, const MeshLimits& limits) : file_(file), limits_(limits) {}

  TriangleMesh Parse(const std::string& text) {
    if (text.size() > limits_.max_bytes)
      throw Error(file_ + ": file is " + std::to_string(text.size()) + " bytes; the limit is " +
                  std::to_string(limits_.max_bytes));
    size_t pos = 0;
    while (pos < text.size()) {
      size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      ++line_;
      std::string_view line(text.data() + pos, end - pos);
      pos = end + 1;
      if (size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
      std::vector<std::string_view> tokens = Tokens(line);
      if (!tokens.empty()) Statement(tokens);
    }
    if (mesh_.triangles.empty()) throw Error(file_ + ": the file has no faces");
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const {
    throw Error(file_ + ":" + std::to_string(line_) + ": " + message);
  }

  double Number(std::string_view token, const char* what) const {
    std::optional<double> value = ParseDouble(token);
    if (!value) Fail(std::string(what) + " \"" + std::string(token) + "\" is not a number");
    if (!std::isfinite(*value)) Fail(std::string(what) + " \"" + std::string(token) + "\" is not a finite number");
    return *value;
  }

  void Statement(const std::vector<std::string_view>& t) {
    std::string_view keyword = t[0];
    size_t args = t.size() - 1;
    if (keyword == "v") {
      if (args != 3 && args != 4 && args != 6)
        Fail("a vertex needs 3 coordinates (x y z), got " + std::to_string(args) + " values");
      if (mesh_.positions.size() >= limits_.max_vertices)
        Fail("more than " + std::to_string(limits_.max_vertices) + " vertices");
      mesh_.positions.push_back(
          {Number(t[1], "vertex coordinate"), Number(t[2], "vertex coordinate"), Number(t[3], "vertex coordinate")});
      for (size_t k = 4; k < t.size(); ++k) Number(t[k], "vertex value");
    } else if (keyword == "vt") {
      if (args < 1 || args > 3)
        Fail("a texture coordinate needs 1 to 3 values (u [v [w]]), got " + std::to_string(args));
      if (mesh_.uvs.size() >= limits_.max_vertices)
        Fail("more than " + std::to_string(limits_.max_vertices) + " texture coordinates");
      mesh_.uvs.push_back({Number(t[1], "texture coordinate"), args >= 2 ? Number(t[2], "texture coordinate") : 0.0});
    } else if (keyword == "vn") {
      if (args != 3) Fail("a normal needs 3 values (x y z), got " + std::to_string(args));
      for (size_t k = 1; k < t.size(); ++k) Number(t[k], "normal component");
      ++normals_;
    } else if (keyword == "f") {
      Face(t);
    } else if (keyword == "o" || keyword == "g" || keyword == "s" || keyword == "mtllib" || keyword == "usemtl" ||
               keyword == "p" || keyword == "l") {
      // Grouping, materials, points and lines: nothing to triangulate.
    } else {
      Fail("unsupported statement \"" + std::string(keyword) +
           "\" (this reader takes v, vt, vn and f; o, g, s, mtllib, usemtl, p and l are ignored)");
    }
  }

  // A 1-based or negative (relative) index into a list of `count` entries.
  uint32_t Resolve(std::string_view token, size_t count, const char* what, const char* plural) const {
    std::optional<long long> index = ParseInteger(token);
    if (!index) Fail(std::string(what) + " index \"" + std::string(token) + "\" is not an integer");
    if (*index == 0) Fail(std::string(what) + " index 0 is invalid; OBJ indices start at 1");
    long long resolved = *index > 0 ? *index - 1 : static_cast<long long>(count) + *index;
    if (resolved < 0 || resolved >= static_cast<long long>(count))
      Fail(std::string(what) + " index " + std::string(token) + " is out of range (" + std::to_string(count) + " " +
           (count == 1 ? what : plural) + " defined so far)");
    return static_cast<uint32_t>(resolved);
  }

  void Face(const std::vector<std::string_view>& t) {
    size_t corners = t.size() - 1;
    if (corners < 3) Fail("a face needs at least 3 vertices, got " + std::to_string(corners));
    if (corners > limits_.max_polygon_vertices)
      Fail("a face of " + std::to_string(corners) + " vertices; the limit is " +
           std::to_string(limits_.max_polygon_vertices));
    std::vector<uint32_t> positions, uvs;
    for (size_t k = 1; k < t.size(); ++k) {
      std::string_view corner = t[k];
      size_t slash1 = corner.find('/');
      size_t slash2 = slash1 == std::string_view::npos ? std::string_view::npos : corner.find('/', slash1 + 1);
      std::string_view vertex = corner.substr(0, slash1);
      std::string_view uv =
          slash1 == std::string_view::npos ? std::string_view() : corner.substr(slash1 + 1, slash2 - slash1 - 1);
      std::string_view normal = slash2 == std::string_view::npos ? std::string_view() : corner.substr(slash2 + 1);
      bool malformed = vertex.empty() || (slash2 != std::string_view::npos && normal.empty()) ||
                       (slash1 != std::string_view::npos && slash2 == std::string_view::npos && uv.empty()) ||
                       normal.find('/') != std::string_view::npos;
      if (malformed) Fail("\"" + std::string(corner) + "\" is not a face vertex (expected i, i/t, i/t/n or i//n)");
      positions.push_back(Resolve(vertex, mesh_.positions.size(), "vertex", "vertices"));
      if (!uv.empty()) uvs.push_back(Resolve(uv, mesh_.uvs.size(), "texture coordinate", "texture coordinates"));
      if (!normal.empty()) Resolve(normal, normals_, "normal", "normals");
    }
    if (!uvs.empty() && uvs.size() != positions.size())
      Fail("the face mixes vertices with and without texture coordinates");
    bool with_uvs = !uvs.empty();
    if (faces_ > 0 && with_uvs != faces_have_uvs_)
      Fail(with_uvs ? "the face has texture coordinates, but the faces above it do not"
                    : "the face has no texture coordinates, but the faces above it do");
    faces_have_uvs_ = with_uvs;
    ++faces_;
    if (mesh_.triangles.size() + corners - 2 > limits_.max_triangles)
      Fail("more than " + std::to_string(limits_.max_triangles) + " triangles");
    FanTriangulate(positions, mesh_.triangles);
    if (with_uvs) FanTriangulate(uvs, mesh_.triangle_uvs);
  }

  std::string file_;
  MeshLimits limits_;
  TriangleMesh mesh_;
  size_t line_ = 0, normals_ = 0, faces_ = 0;
  bool faces_have_uvs_ = false;
};

// ---- PLY ------------------------------------------------------------------

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<PlyType> PlyTypeNamed(std::string_view name) {
  if (name == "char" || name == "int8") return PlyType::kInt8;
  if (name == "uchar" || name == "uint8") return PlyType::kUint8;
  if (name == "short" || name == "int16") return PlyType::kInt16;
  if (name == "ushort" || name == "uint16") return PlyType::kUint16;
  if (name == "int" || name == "int32") return PlyType::kInt32;
  if (name == "uint" || name == "uint32") return PlyType::kUint32;
  if (name == "float" || name == "float32") return PlyType::kFloat32;
  if (name == "double" || name == "float64") return PlyType::kFloat64;
  return std::nullopt;
}

size_t PlyTypeSize(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 1;
}

bool PlyTypeIsInteger(PlyType t) { return t != PlyType::kFloat32 && t != PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;

  int find(std::initializer_list<const char*> names) const {
    for (const char* n : names)
      for (size_t i = 0; i < properties.size(); ++i)
        if (properties[i].name == n) return static_cast<int>(i);
    return -1;
  }
  // Bytes one instance takes at least in a binary body (lists: their count only).
  size_t min_binary_size() const {
    size_t s = 0;
    for (const PlyProperty& p : properties) s += PlyTypeSize(p.is_list ? p.count_type : p.type);
    return s;
  }
};

// Values of the body, ascii or little-endian binary; `where` labels errors.
class PlyBody {
 public:
  PlyBody(const std::string& bytes, size_t start, bool binary, const std::string& file)
      : bytes_(bytes), pos_(start), binary_(binary), file_(file) {}

  size_t remaining() const { return bytes_.size() - pos_; }

  double Read(PlyType type, const std::string& where) {
    return binary_ ? ReadBinary(type, where) : ReadAscii(type, where);
  }

  [[noreturn]] void Fail(const std::string& where, const std::string& message) const {
    throw Error(file_ + ": " + where + ": " + message);
  }

 private:
  double ReadBinary(PlyType type, const std::string& where) {
    size_t n = PlyTypeSize(type);
    if (remaining() < n) Fail(where, "the file ends early");
    unsigned char b[8] = {};
    std::memcpy(b, bytes_.data() + pos_, n);
    pos_ += n;
    uint64_t u = 0;
    for (size_t i = 0; i < n; ++i) u |= static_cast<uint64_t>(b[i]) << (8 * i);  // little endian
    switch (type) {
      case PlyType::kInt8:
        return static_cast<int8_t>(u);
      case PlyType::kUint8:
        return static_cast<uint8_t>(u);
      case PlyType::kInt16:
        return static_cast<int16_t>(u);
      case PlyType::kUint16:
        return static_cast<uint16_t>(u);
      case PlyType::kInt32:
        return static_cast<int32_t>(u);
      case PlyType::kUint32:
        return static_cast<uint32_t>(u);
      case PlyType::kFloat32: {
        uint32_t bits = static_cast<uint32_t>(u);
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
      }
      case PlyType::kFloat64: {
        double d;
        std::memcpy(&d, &u, 8);
        return d;
      }
    }
    return 0;
  }

  double ReadAscii(PlyType type, const std::string& where) {
    while (pos_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    if (pos_ >= bytes_.size()) Fail(where, "the file ends early");
    size_t start = pos_;
    while (pos_ < bytes_.size() && !std::isspace(static_cast<unsigned char>(bytes_[pos_]))) ++pos_;
    std::string_view token(bytes_.data() + start, pos_ - start);
    std::optional<double> value = ParseDouble(token);
    if (!value) Fail(where, "\"" + std::string(token) + "\" is not a number");
    if (PlyTypeIsInteger(type) && (!std::isfinite(*value) || *value != std::floor(*value)))
      Fail(where, "\"" + std::string(token) + "\" is not an integer");
    return *value;
  }

  const std::string& bytes_;
  size_t pos_;
  bool binary_;
  std::string file_;
};

// The header: text lines up to "end_header", each checked as read.
class PlyHeader {
 public:
  PlyHeader(const std::string& file, const MeshLimits& limits) : file_(file), limits_(limits) {}

  std::vector<PlyElement> elements;
  bool binary = false;
  size_t body_start = 0;  // the byte after the "end_header" line

  void Read(const std::string& bytes) {
    bool have_format = false;
    size_t pos = 0;
    bool ended = false;
    while (!ended) {
      size_t end = bytes.find('\n', pos);
      if (end == std::string::npos || line_no_ > 10000) throw Error(file_ + ": the PLY header has no end_header line");
      ++line_no_;
      std::string_view line(bytes.data() + pos, end - pos);
      pos = end + 1;
      std::vector<std::string_view> t = Tokens(line);
      if (line_no_ == 1) {
        if (t.size() != 1 || t[0] != "ply") throw Error(file_ + ": not a PLY file (the first line is not \"ply\")");
        continue;
      }
      if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
      if (t[0] == "format") {
        ReadFormat(t);
        have_format = true;
      } else if (t[0] == "element") {
        ReadElement(t);
      } else if (t[0] == "property") {
        if (elements.empty()) Fail("a property before any element");
        elements.back().properties.push_back(ReadProperty(t));
      } else if (t[0] == "end_header") {
        ended = true;
      } else {
        Fail("unknown header keyword \"" + std::string(t[0]) + "\"");
      }
    }
    if (!have_format) throw Error(file_ + ": the PLY header has no format line");
    body_start = pos;
  }

 private:
  [[noreturn]] void Fail(const std::string& message) const {
    throw Error(file_ + ": header line " + std::to_string(line_no_) + ": " + message);
  }

  void ReadFormat(const std::vector<std::string_view>& t) {
    if (t.size() != 3 || t[2] != "1.0") Fail("expected \"format ascii 1.0\" or \"format binary_little_endian 1.0\"");
    if (t[1] == "binary_big_endian")
      Fail("binary_big_endian PLY is not supported; convert it to binary_little_endian or ascii");
    if (t[1] != "ascii" && t[1] != "binary_little_endian") Fail("unknown format \"" + std::string(t[1]) + "\"");
    binary = t[1] == "binary_little_endian";
  }

  void ReadElement(const std::vector<std::string_view>& t) {
    if (t.size() != 3) Fail("expected \"element NAME COUNT\"");
    std::optional<long long> count = ParseInteger(t[2]);
    if (!count || *count < 0) Fail("element count \"" + std::string(t[2]) + "\" is not a non-negative integer");
    size_t limit = t[1] == "face" ? limits_.max_triangles : limits_.max_vertices;
    if (static_cast<unsigned long long>(*count) > limit)
      Fail(std::to_string(*count) + " " + std::string(t[1]) + " elements; the limit is " + std::to_string(limit));
    elements.push_back({std::string(t[1]), static_cast<size_t>(*count), {}});
  }

  PlyProperty ReadProperty(const std::vector<std::string_view>& t) const {
    if (t.size() == 5 && t[1] == "list") {
      auto count_type = PlyTypeNamed(t[2]);
      auto item_type = PlyTypeNamed(t[3]);
      if (!count_type || !item_type || !PlyTypeIsInteger(*count_type))
        Fail("expected \"property list COUNT_TYPE ITEM_TYPE NAME\" with an integer COUNT_TYPE");
      return {std::string(t[4]), *item_type, true, *count_type};
    }
    if (t.size() == 3) {
      auto type = PlyTypeNamed(t[1]);
      if (!type) Fail("unknown property type \"" + std::string(t[1]) + "\"");
      return {std::string(t[2]), *type, false, PlyType::kUint8};
    }
    Fail("expected \"property TYPE NAME\" or \"property list COUNT_TYPE ITEM_TYPE NAME\"");
  }

  const std::string& file_;
  const MeshLimits& limits_;
  size_t line_no_ = 0;
};

// Where the mesh sits among the header's elements and properties.
struct PlyLayout {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  int ix = -1, iy = -1, iz = -1, iu = -1, iv = -1;
  bool with_uvs = false;
  int ilist = -1;  // the face's vertex indices
};

PlyLayout FindPlyLayout(const std::vector<PlyElement>& elements, const std::string& file) {
  PlyLayout l;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") l.vertex = &e;
    if (e.name == "face") l.face = &e;
  }
  if (!l.vertex) throw Error(file + ": the PLY file has no vertex element");
  if (!l.face || l.face->count == 0) throw Error(file + ": the PLY file has no faces");
  l.ix = l.vertex->find({"x"}), l.iy = l.vertex->find({"y"}), l.iz = l.vertex->find({"z"});
  for (auto [index, name] : {std::pair{l.ix, "x"}, std::pair{l.iy, "y"}, std::pair{l.iz, "z"}})
    if (index < 0 || l.vertex->properties[index].is_list)
      throw Error(file + ": the vertex element has no scalar property " + name);
  l.iu = l.vertex->find({"u", "s", "texture_u"}), l.iv = l.vertex->find({"v", "t", "texture_v"});
  l.with_uvs = l.iu >= 0 && l.iv >= 0 && !l.vertex->properties[l.iu].is_list && !l.vertex->properties[l.iv].is_list;
  l.ilist = l.face->find({"vertex_indices", "vertex_index"});
  if (l.ilist < 0 || !l.face->properties[l.ilist].is_list)
    throw Error(file + ": the face element has no list property vertex_indices");
  if (!PlyTypeIsInteger(l.face->properties[l.ilist].type))
    throw Error(file + ": the face property vertex_indices must hold integers");
  return l;
}

// One face's polygon, fanned into triangles.
void ReadPlyFace(PlyBody& body, const PlyProperty& prop, double count, const std::string& where,
                 const PlyLayout& layout, const MeshLimits& limits, TriangleMesh* mesh) {
  if (count < 3) body.Fail(where, "a face needs at least 3 vertices, got " + FormatCount(count));
  if (count > static_cast<double>(limits.max_polygon_vertices))
    body.Fail(where, "a face of " + FormatCount(count) + " vertices; the limit is " +
                         std::to_string(limits.max_polygon_vertices));
  std::vector<uint32_t> polygon;
  for (int c = 0; c < static_cast<int>(count); ++c) {
    double index = body.Read(prop.type, where);
    if (index < 0 || index >= static_cast<double>(layout.vertex->count))
      body.Fail(where, "vertex index " + FormatCount(index) + " is out of range (" +
                           std::to_string(layout.vertex->count) + " vertices)");
    polygon.push_back(static_cast<uint32_t>(index));
  }
  if (mesh->triangles.size() + polygon.size() - 2 > limits.max_triangles)
    body.Fail(where, "more than " + std::to_string(limits.max_triangles) + " triangles");
  FanTriangulate(polygon, mesh->triangles);
}

// One instance of element `e`: a vertex's position and uv, a face's triangles,
// and any other element's values read past.
void ReadPlyInstance(PlyBody& body, const PlyElement& e, size_t n, const PlyLayout& layout, const MeshLimits& limits,
                     TriangleMesh* mesh) {
  const bool is_vertex = &e == layout.vertex, is_face = &e == layout.face;
  std::string where = e.name + " " + std::to_string(n);
  std::array<double, 3> p{};
  std::array<double, 2> uv{};
  for (size_t k = 0; k < e.properties.size(); ++k) {
    const PlyProperty& prop = e.properties[k];
    if (prop.is_list) {
      double count = body.Read(prop.count_type, where);
      if (is_face && static_cast<int>(k) == layout.ilist) {
        ReadPlyFace(body, prop, count, where, layout, limits, mesh);
      } else {
        if (count < 0 || count > 1e6) body.Fail(where, "a list of " + FormatCount(count) + " items");
        for (int c = 0; c < static_cast<int>(count); ++c) body.Read(prop.type, where);
      }
      continue;
    }
    double value = body.Read(prop.type, where);
    if (!is_vertex) continue;
    int ki = static_cast<int>(k);
    if (ki == layout.ix || ki == layout.iy || ki == layout.iz ||
        (layout.with_uvs && (ki == layout.iu || ki == layout.iv))) {
      if (!std::isfinite(value))
        body.Fail(where, "property " + prop.name + " is " + (std::isnan(value) ? "NaN" : "infinite") +
                             "; coordinates must be finite");
      if (ki == layout.ix) p[0] = value;
      if (ki == layout.iy) p[1] = value;
      if (ki == layout.iz) p[2] = value;
      if (ki == layout.iu) uv[0] = value;
      if (ki == layout.iv) uv[1] = value;
    }
  }
  if (is_vertex) {
    mesh->positions.push_back(p);
    if (layout.with_uvs) mesh->uvs.push_back(uv);
  }
}

TriangleMesh ParsePlyImpl(const std::string& bytes, const std::string& file, const MeshLimits& limits) {
  if (bytes.size() > limits.max_bytes)
    throw Error(file + ": file is " + std::to_string(bytes.size()) + " bytes; the limit is " +
                std::to_string(limits.max_bytes));
  PlyHeader header(file, limits);
  header.Read(bytes);
  const PlyLayout layout = FindPlyLayout(header.elements, file);

  PlyBody body(bytes, header.body_start, header.binary, file);
  // Refuse counts the file cannot hold before allocating for them.
  size_t needed = 0;
  for (const PlyElement& e : header.elements)
    needed += e.count * (header.binary ? e.min_binary_size() : e.properties.size());
  if (needed > body.remaining())
    throw Error(file + ": the header declares more data than the file holds (" + std::to_string(needed) +
                (header.binary ? " bytes" : " values") + " at least, " + std::to_string(body.remaining()) +
                " bytes left)");

  TriangleMesh mesh;
  for (const PlyElement& e : header.elements) {
    if (&e == layout.vertex) {
      mesh.positions.reserve(e.count);
      if (layout.with_uvs) mesh.uvs.reserve(e.count);
    }
    for (size_t n = 0; n < e.count; ++n) ReadPlyInstance(body, e, n, layout, limits, &mesh);
  }
  if (layout.with_uvs) mesh.triangle_uvs = mesh.triangles;
  return mesh;
}

}  // namespace

TriangleMesh ParseObj(const std::string& text, const std::string& file, const MeshLimits& limits) {
  return ObjParser(file, limits).Parse(text);
}

TriangleMesh ParsePly(const std::string& bytes, const std::string& file, const MeshLimits& limits) {
  return ParsePlyImpl(bytes, file, limits);
}

TriangleMesh ReadMesh(const std::string& path, const MeshLimits& limits) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension != ".obj" && extension != ".ply")
    throw Error(path + ": unknown mesh format \"" + extension + "\"; expected .obj or .ply");
  std::error_code ec;
  auto size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(path + ": cannot read: " + ec.message());
  if (size > limits.max_bytes)
    throw Error(path + ": file is " + std::to_string(size) + " bytes; the limit is " +
                std::to_string(limits.max_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open for reading");
  std::ostringstream contents;
  contents << in.rdbuf();
  return extension == ".obj" ? ParseObj(contents.str(), path, limits) : ParsePly(contents.str(), path, limits);
}

}  // namespace layerlab

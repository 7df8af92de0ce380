#include "layerlab/framework/lightfield_io.h"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <utility>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/file_kind.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/lightfield_checks.h"
#include "layerlab/framework/parallel.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/progress.h"
#include "layerlab/framework/staged_output.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

// "views/r{row:02}_c{col:02}.exr" with row and col filled in.
std::string FillPattern(const std::string& pattern, int row, int col) {
  std::string out;
  for (size_t i = 0; i < pattern.size();) {
    if (pattern[i] == '{') {
      size_t close = pattern.find('}', i);
      std::string field = pattern.substr(i + 1, close - i - 1);
      std::string name = field.substr(0, field.find(':'));
      int width = field.find(':') == std::string::npos ? 0 : std::stoi(field.substr(field.find(':') + 1));
      std::string number = std::to_string(name == "row" ? row : col);
      if (static_cast<int>(number.size()) < width) number.insert(0, width - number.size(), '0');
      out += number;
      i = close + 1;
    } else {
      out += pattern[i++];
    }
  }
  return out;
}

// Refuses patterns that could name files outside the folder, and unknown fields.
void CheckPattern(Params& manifest, const std::string& key, const std::string& pattern) {
  fs::path p(pattern);
  if (p.is_absolute()) manifest.fail(key, "\"" + pattern + "\" must be relative to the light-field folder");
  for (const fs::path& part : p)
    if (part == "..") manifest.fail(key, "\"" + pattern + "\" escapes the light-field folder ('..')");
  static const std::regex field(R"(\{(row|col)(:0?[1-9])?\})");
  std::string rest = std::regex_replace(pattern, field, "");
  if (rest.find('{') != std::string::npos || rest.find('}') != std::string::npos)
    manifest.fail(key, "\"" + pattern + "\" may use only the fields {row}, {col}, {row:02} and {col:02}");
  if (pattern.find("{row") == std::string::npos || pattern.find("{col") == std::string::npos)
    manifest.fail(key, "\"" + pattern + "\" must contain both {row} and {col}");
}

// Files in the pattern's folder that look like views but are not declared.
void RefuseExtraFiles(const std::string& folder, const std::string& pattern, const LightFieldGeometry& g) {
  fs::path dir = fs::path(folder) / fs::path(pattern).parent_path();
  std::string name_pattern = fs::path(pattern).filename().string();
  std::string regex_text;
  for (size_t i = 0; i < name_pattern.size();) {
    if (name_pattern[i] == '{') {
      regex_text += "([0-9]+)";
      i = name_pattern.find('}', i) + 1;
    } else {
      char c = name_pattern[i++];
      if (std::string(".^$|()[]*+?\\").find(c) != std::string::npos) regex_text += '\\';
      regex_text += c;
    }
  }
  std::regex re(regex_text);
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::string name = entry.path().filename().string();
    std::smatch m;
    if (!std::regex_match(name, m, re)) continue;
    bool row_first = name_pattern.find("{row") < name_pattern.find("{col");
    auto number = [](const std::string& digits) {  // beyond any view count when it overflows
      long v = LONG_MAX;
      std::from_chars(digits.data(), digits.data() + digits.size(), v);
      return v;
    };
    long row = number(m[row_first ? 1 : 2]), col = number(m[row_first ? 2 : 1]);
    if (row >= g.views_y || col >= g.views_x ||
        FillPattern(pattern, row, col) != (fs::path(pattern).parent_path() / name).string())
      throw Error((fs::path(folder) / "lightfield.json").string() + ": extra view file " +
                  (fs::path(pattern).parent_path() / name).string() + " (the manifest declares " +
                  std::to_string(g.views_y) + " x " + std::to_string(g.views_x) + " views)");
  }
}

// Every view gets a file name of its own, within the file system's limits.
void CheckViewNames(Params& manifest, const std::string& key, const std::string& pattern, const LightFieldGeometry& g) {
  std::map<std::string, std::pair<int, int>> seen;
  for (int r = 0; r < g.views_y; ++r)
    for (int c = 0; c < g.views_x; ++c) {
      const std::string name = FillPattern(pattern, r, c);
      if (name.size() >= PATH_MAX)
        manifest.fail(key,
                      "view paths of " + std::to_string(name.size()) + " bytes are beyond the file system's limit");
      for (const fs::path& part : fs::path(name))
        if (part.string().size() > NAME_MAX)
          manifest.fail(key, "\"" + part.string().substr(0, 40) + "...\" is " + std::to_string(part.string().size()) +
                                 " bytes, beyond the file system's limit of " + std::to_string(NAME_MAX) +
                                 " for a name");
      auto [it, fresh] = seen.emplace(name, std::make_pair(r, c));
      if (!fresh)
        manifest.fail(key, "\"" + pattern + "\" maps views (row " + std::to_string(it->second.first) + ", col " +
                               std::to_string(it->second.second) + ") and (row " + std::to_string(r) + ", col " +
                               std::to_string(c) + ") to one file, " + name);
    }
}

struct Manifest {
  std::string path;
  LightFieldGeometry geometry;
  std::string views_pattern, depth_pattern, scene;
};

// Where a light field comes from, for a path that is not one.
constexpr const char* kMakeOne =
    "Render one from a target scene with `layerlab render-target TARGET.json --out LF_DIR`, or give the target scene "
    "itself (--target-scene TARGET.json, or \"target_scene\" in the scene's \"solve\" section); the folder format: "
    "docs/lightfield-format.md";

Manifest ReadManifest(const std::string& folder) {
  for (const std::string& line : FinishPendingSwitchOvers(folder)) Note(line);
  std::string manifest_path = (fs::path(folder) / "lightfield.json").string();
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    if (ec && ec != std::errc::no_such_file_or_directory)
      RequireFolder(folder, "light-field folder");  // a loop, an overlong name
    throw Error(folder + ": not a light-field folder (" +
                (fs::is_regular_file(folder, ec) ? "a file" : "no such directory") + "). " + kMakeOne);
  }
  if (!fs::exists(fs::symlink_status(manifest_path, ec)))
    throw Error(folder + ": not a light-field folder (no lightfield.json). " + kMakeOne);
  RequireRegularFile(manifest_path, "manifest");
  RequireInsideFolder(manifest_path, folder, "manifest");
  nlohmann::json doc = ReadJsonFile(manifest_path);
  Params m(doc, {manifest_path, ""});

  std::string format = m.string("format");
  if (format != kLightFieldFormat)
    m.fail("format",
           "unknown light-field format \"" + format + "\"; this layerlab reads \"" + kLightFieldFormat + "\"");
  LightFieldGeometry g;
  g.origin_z_m = m.quantity("origin_plane_z", Dimension::kLength);
  m.require_range("origin_plane_z", g.origin_z_m, 0.0, 1e6, true, false);
  ReadLightFieldWindow(m.object("window"), &g);
  Params resolution = m.object("resolution");
  g.cols = static_cast<int>(resolution.integer("cols", 1, kMaxPixelsPerAxis));
  g.rows = static_cast<int>(resolution.integer("rows", 1, kMaxPixelsPerAxis));
  resolution.check_all_read();
  Params views = m.object("views");
  g.views_y = static_cast<int>(views.integer("rows", 1, kMaxViewsPerAxis));
  g.views_x = static_cast<int>(views.integer("cols", 1, kMaxViewsPerAxis));
  g.eyebox_width_m = views.quantity("eyebox_width", Dimension::kLength);
  g.eyebox_height_m = views.quantity("eyebox_height", Dimension::kLength);
  views.require_range("eyebox_width", g.eyebox_width_m, 0.0, 1.0, false, false);
  views.require_range("eyebox_height", g.eyebox_height_m, 0.0, 1.0, false, false);
  views.check_all_read();
  std::string color = m.string("color", "linear-rec709");
  if (color != "linear-rec709") m.fail("color", "unknown color encoding \"" + color + "\"; expected \"linear-rec709\"");
  std::string views_pattern = m.string("views_pattern");
  CheckPattern(m, "views_pattern", views_pattern);
  std::string depth_pattern = m.string("depth_pattern", "");
  if (!depth_pattern.empty()) CheckPattern(m, "depth_pattern", depth_pattern);
  std::string scene = m.string("scene", "");
  m.check_all_read();
  CheckViewNames(m, "views_pattern", views_pattern, g);
  if (!depth_pattern.empty()) CheckViewNames(m, "depth_pattern", depth_pattern, g);
  // The limits every geometry is held to (a Python one too), the number of rays among them.
  CheckLightFieldGeometry(g, [&](const std::string& field, const std::string& why) {
    static const std::map<std::string, std::string> pointer = {{"origin_z", "/origin_plane_z"},
                                                               {"window_left", "/window/left"},
                                                               {"window_top", "/window/top"},
                                                               {"window_width", "/window/width"},
                                                               {"window_height", "/window/height"},
                                                               {"cols", "/resolution/cols"},
                                                               {"rows", "/resolution/rows"},
                                                               {"views_x", "/views/cols"},
                                                               {"views_y", "/views/rows"},
                                                               {"eyebox_width", "/views/eyebox_width"},
                                                               {"eyebox_height", "/views/eyebox_height"}};
    throw Error(Location{manifest_path, pointer.count(field) ? pointer.at(field) : ""}, why);
  });
  return {manifest_path, g, views_pattern, depth_pattern, scene};
}

}  // namespace

void ReadLightFieldWindow(Params window, LightFieldGeometry* g) {
  g->window_left_m = window.quantity("left", Dimension::kLength);
  g->window_top_m = window.quantity("top", Dimension::kLength);
  g->window_width_m = window.quantity("width", Dimension::kLength);
  g->window_height_m = window.quantity("height", Dimension::kLength);
  window.require_range("width", g->window_width_m, 0.0, 1e6, true, false);
  window.require_range("height", g->window_height_m, 0.0, 1e6, true, false);
  window.check_all_read();
}

LightFieldGeometry ReadLightFieldGeometry(const std::string& folder) { return ReadManifest(folder).geometry; }

namespace {

// Rows [first, first + count) of the `have` rows of an axis (count 0: all of them), or an Error naming them.
std::pair<int, int> RowsAsked(const std::string& manifest_path, const std::string& rows, const std::string& has,
                              int first, int count, int have) {
  if (count <= 0) return {0, have};
  if (first < 0 || first + count > have)
    throw Error(manifest_path + ": " + rows + " " + std::to_string(first) + " to " + std::to_string(first + count - 1) +
                " were asked for; " + has + " " + std::to_string(have));
  return {first, count};
}

}  // namespace

LightField ReadLightField(const std::string& folder, const LightFieldReadOptions& options) {
  const Manifest manifest = ReadManifest(folder);
  // References, not a structured binding: the lambda below captures them, which
  // clang before 16 refuses for bindings.
  const std::string& manifest_path = manifest.path;
  const LightFieldGeometry& g = manifest.geometry;
  const std::string& views_pattern = manifest.views_pattern;
  const std::string& depth_pattern = manifest.depth_pattern;
  const std::pair<int, int> view_rows = RowsAsked(manifest_path, "view rows", "the light field has",
                                                  options.first_view_row, options.view_rows, g.views_y);
  const std::pair<int, int> pixel_rows =
      RowsAsked(manifest_path, "pixel rows", "a view has", options.first_pixel_row, options.pixel_rows, g.rows);
  const int first_row = view_rows.first, rows = view_rows.second;
  LightFieldGeometry tile = options.view_rows > 0 ? g.ViewRows(first_row, rows) : g;
  if (options.pixel_rows > 0) tile = tile.PixelRows(pixel_rows.first, pixel_rows.second);
  LightField lf(tile);
  lf.scene = manifest.scene;

  for (int r = first_row; r < first_row + rows; ++r)
    for (int c = 0; c < g.views_x; ++c) {
      std::string file = (fs::path(folder) / FillPattern(views_pattern, r, c)).string();
      std::error_code ec;
      if (!fs::exists(fs::symlink_status(file, ec)))
        throw Error(manifest_path + ": view (row " + std::to_string(r) + ", col " + std::to_string(c) +
                    ") is missing: " + file);
      RequireRegularFile(file, "view");  // never opened otherwise: a FIFO would block
      RequireInsideFolder(file, folder, "view");
    }
  RefuseExtraFiles(folder, views_pattern, g);

  bool with_depth = options.load_depth && !depth_pattern.empty();
  if (with_depth) lf.depth.assign(lf.geometry.ray_count(), 0.0f);
  const size_t pixels = lf.geometry.pixels_per_view(), skipped = size_t(pixel_rows.first) * g.cols;
  ParallelFor(lf.geometry.view_count(), [&](size_t v) {
    int r = first_row + static_cast<int>(v / g.views_x), c = static_cast<int>(v % g.views_x);
    std::string file = (fs::path(folder) / FillPattern(views_pattern, r, c)).string();
    Image image = ReadExr(file, {"R", "G", "B"});
    if (image.width != g.cols || image.height != g.rows)
      throw Error(file + ": is " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                  " pixels; the manifest declares " + std::to_string(g.cols) + " x " + std::to_string(g.rows));
    std::copy_n(image.pixels.begin() + long(skipped * 3), pixels * 3, lf.view(v));
    if (!with_depth) return;
    std::string depth_file = (fs::path(folder) / FillPattern(depth_pattern, r, c)).string();
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(depth_file, ec)))
      throw Error(manifest_path + ": depth_pattern is given but " + depth_file + " is missing");
    RequireRegularFile(depth_file, "depth map");
    RequireInsideFolder(depth_file, folder, "depth map");
    Image depth = ReadExr(depth_file, {"Z"});
    if (depth.width != g.cols || depth.height != g.rows)
      throw Error(depth_file + ": is " + std::to_string(depth.width) + " x " + std::to_string(depth.height) +
                  " pixels; the manifest declares " + std::to_string(g.cols) + " x " + std::to_string(g.rows));
    std::copy_n(depth.pixels.begin() + long(skipped), pixels, lf.depth.begin() + long(v * pixels));
  });
  return lf;
}

std::vector<std::string> WriteLightField(const LightField& lf, const std::string& folder) {
  const LightFieldGeometry& g = lf.geometry;
  if (lf.rgb.size() != g.ray_count() * 3 || (!lf.depth.empty() && lf.depth.size() != g.ray_count()))
    throw Error(folder + ": internal error: light-field buffers do not match the geometry");
  if (g.is_tile()) throw Error(folder + ": internal error: a tile of a light field is not a light field to write");
  const std::string views_pattern = "views/r{row:02}_c{col:02}.exr";
  const std::string depth_pattern = "depth/r{row:02}_c{col:02}.exr";
  std::error_code ec;
  fs::create_directories(fs::path(folder) / "views", ec);
  if (!lf.depth.empty()) fs::create_directories(fs::path(folder) / "depth", ec);
  if (ec) throw Error(folder + ": cannot create the folder: " + ec.message());

  const size_t pixels = g.pixels_per_view();
  ParallelFor(g.view_count(), [&](size_t v) {
    int r = static_cast<int>(v / g.views_x), c = static_cast<int>(v % g.views_x);
    Image image{g.cols, g.rows, {"R", "G", "B"}, std::vector<float>(lf.view(v), lf.view(v) + pixels * 3)};
    WriteExr((fs::path(folder) / FillPattern(views_pattern, r, c)).string(), image);
    if (lf.depth.empty()) return;
    Image depth{
        g.cols, g.rows, {"Z"}, std::vector<float>(lf.depth.begin() + v * pixels, lf.depth.begin() + (v + 1) * pixels)};
    WriteExr((fs::path(folder) / FillPattern(depth_pattern, r, c)).string(), depth);
  });

  nlohmann::json manifest = {{"format", kLightFieldFormat},
                             {"origin_plane_z", g.origin_z_m},
                             {"window",
                              {{"left", g.window_left_m},
                               {"top", g.window_top_m},
                               {"width", g.window_width_m},
                               {"height", g.window_height_m}}},
                             {"resolution", {{"cols", g.cols}, {"rows", g.rows}}},
                             {"views",
                              {{"rows", g.views_y},
                               {"cols", g.views_x},
                               {"eyebox_width", g.eyebox_width_m},
                               {"eyebox_height", g.eyebox_height_m}}},
                             {"color", "linear-rec709"},
                             {"views_pattern", views_pattern},
                             {"scene", lf.scene}};
  if (!lf.depth.empty()) manifest["depth_pattern"] = depth_pattern;
  WriteFileAtomically((fs::path(folder) / "lightfield.json").string(), manifest.dump(2) + "\n");
  std::vector<std::string> written;
  for (int r = 0; r < g.views_y; ++r)
    for (int c = 0; c < g.views_x; ++c) {
      written.push_back(FillPattern(views_pattern, r, c));
      if (!lf.depth.empty()) written.push_back(FillPattern(depth_pattern, r, c));
    }
  written.push_back("lightfield.json");
  return written;
}

ContentDigest& AddGeometry(ContentDigest& digest, const LightFieldGeometry& g) {
  const double numbers[] = {g.origin_z_m,      g.window_left_m,   g.window_top_m,    g.window_width_m,
                            g.window_height_m, g.eyebox_width_m,  g.eyebox_height_m, double(g.cols),
                            double(g.rows),    double(g.views_x), double(g.views_y)};
  digest.add(numbers, sizeof numbers);
  if (g.is_tile()) {  // a whole light field keys as it always did
    const double block[] = {double(g.first_view_row), double(g.all_view_rows)};
    digest.add(block, sizeof block);
  }
  if (g.all_pixel_rows != 0) {
    const double rows[] = {double(g.first_pixel_row), double(g.all_pixel_rows)};
    digest.add(rows, sizeof rows);
  }
  return digest;
}

std::string LightFieldDigest(const LightField& lf) {
  ContentDigest digest;
  return AddGeometry(digest, lf.geometry).add(lf.rgb.data(), lf.rgb.size() * sizeof(float)).hex();
}

}  // namespace layerlab

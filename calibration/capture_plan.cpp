#include "layerlab/calibration/capture_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "layerlab/calibration/measurements.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

std::string Level3(int level) {
  std::string s = std::to_string(level);
  return std::string(3 - std::min<size_t>(3, s.size()), '0') + s;
}

std::string ChessboardFile(const std::string& panel) { return panel + "_chessboard.png"; }
std::string LevelFile(const std::string& panel, int level) { return panel + "_level_" + Level3(level) + ".png"; }
std::string WhiteFile(const std::string& panel) { return panel + "_white.png"; }
std::string BlackFile(const std::string& panel) { return panel + "_black.png"; }

std::string Millimeters(double meters) {
  std::string s = FormatFixed(meters * 1e3, 4);
  while (s.size() > 1 && s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0 mm" : s + " mm";
}

const VirtualLayer& LayerNamed(const DisplaySystem& system, const std::string& panel) {
  for (const VirtualLayer& layer : system.layers)
    if (layer.name == panel) return layer;
  throw Error(system.file + ": the capture plan names panel \"" + panel + "\", which the scene does not have");
}

// What every panel shows while `measured` is measured with image `pattern`.
std::vector<std::pair<std::string, std::string>> Shown(const DisplaySystem& system, const VirtualLayer& measured,
                                                       const std::string& pattern) {
  std::vector<std::pair<std::string, std::string>> show;
  for (const VirtualLayer& layer : system.layers) {
    const std::string file = layer.name == measured.name       ? pattern
                             : layer.branch == measured.branch ? WhiteFile(layer.name)
                                                               : BlackFile(layer.name);
    show.emplace_back(layer.name, std::string(kPatternFolder) + "/" + file);
  }
  return show;
}

}  // namespace

std::array<double, 2> Chessboard::corner(int a, int b) const {
  return {static_cast<double>(left) + (a + 1) * square_pixels - 0.5,
          static_cast<double>(top) + (b + 1) * square_pixels - 0.5};
}

bool Chessboard::dark(int64_t col, int64_t row) const {
  if (col < left || row < top) return false;
  const int64_t a = (col - left) / square_pixels, b = (row - top) / square_pixels;
  return a < squares_x && b < squares_y && (a + b) % 2 == 0;
}

const Chessboard* CapturePlan::chessboard(const std::string& panel) const {
  for (const Chessboard& c : chessboards)
    if (c.panel == panel) return &c;
  return nullptr;
}

std::optional<double> ResponseExponent(const std::string& response) {
  if (response == "linear") return 1.0;
  double g = 0;
  int used = 0;
  if (response.rfind("gamma ", 0) != 0 || std::sscanf(response.c_str() + 6, "%lf%n", &g, &used) != 1 ||
      static_cast<size_t>(used) + 6 != response.size() || !std::isfinite(g) || !(g > 0))
    return std::nullopt;
  return g;
}

std::string ChessboardSquaresProblem(int64_t squares_x, int64_t squares_y) {
  const std::string board = std::to_string(squares_x) + " x " + std::to_string(squares_y) + " squares";
  if (squares_x < 4 || squares_y < 4 || squares_x > 1000 || squares_y > 1000)
    return "a chessboard of " + board +
           ": each side needs 4 to 1000 squares (OpenCV's corner finder needs at least 3 inner corners each way)";
  if (squares_x == squares_y)
    return "a chessboard of " + board +
           ": as many squares across as down would let its corners be found turned by 90 degrees; "
           "use different counts (e.g. 10 6)";
  return "";
}

CapturePlan PlanCaptures(const DisplaySystem& system, const PlanOptions& options) {
  if (system.subframes > 1)
    throw Error(system.file + ": calibration patterns for a time-multiplexed display (" +
                std::to_string(system.subframes) + " subframes) are not supported; calibrate it with one subframe");
  if (std::string why = ChessboardSquaresProblem(options.squares_x, options.squares_y); !why.empty()) throw Error(why);
  if (options.positions.empty()) throw Error("the capture plan needs at least one camera position");
  CapturePlan plan;
  plan.description = "calibration captures of " + system.name;
  std::vector<int> levels = options.levels;
  if (levels.empty()) {
    for (int l = 0; l < 255; l += 16) levels.push_back(l);
    levels.push_back(255);
  }
  for (const VirtualLayer& layer : system.layers) {
    const PanelSpec& p = layer.panel;
    if (p.emitter) continue;  // a backlight's emission shows no chessboard (elements/backlight.cpp)
    Chessboard board;
    board.panel = layer.name;
    board.squares_x = options.squares_x;
    board.squares_y = options.squares_y;
    // One square of white margin on every side, which the corner finder needs.
    board.square_pixels =
        static_cast<int>(std::min(p.active_cols / (options.squares_x + 2), p.active_rows / (options.squares_y + 2)));
    if (board.square_pixels < 4)
      throw Error(system.file + ": panel \"" + layer.name + "\": its active region (" + std::to_string(p.active_cols) +
                  " x " + std::to_string(p.active_rows) + " pixels) cannot hold a " +
                  std::to_string(options.squares_x) + " x " + std::to_string(options.squares_y) +
                  " chessboard with a square of margin and squares of at least 4 pixels; use fewer squares");
    board.left = p.active_left + (p.active_cols - board.squares_x * board.square_pixels) / 2;
    board.top = p.active_top + (p.active_rows - board.squares_y * board.square_pixels) / 2;
    plan.chessboards.push_back(board);
  }
  for (const VirtualLayer& layer : system.layers)
    for (size_t k = 0; k < options.positions.size(); ++k) {
      PlannedCapture c;
      c.photo = layer.name + "_chessboard_" + std::to_string(k) + "." + options.photo_extension;
      c.kind = CaptureKind::kChessboard;
      c.panel = layer.name;
      c.camera_position = options.positions[k];
      c.show = Shown(system, layer, ChessboardFile(layer.name));
      plan.captures.push_back(c);
    }
  for (const VirtualLayer& layer : system.layers)
    for (int level : levels) {
      if (level < 0 || level > 255) throw Error("luminance levels are 8-bit, 0 to 255; got " + std::to_string(level));
      PlannedCapture c;
      c.photo = layer.name + "_level_" + Level3(level) + "." + options.photo_extension;
      c.kind = CaptureKind::kLuminance;
      c.panel = layer.name;
      c.level = level;
      c.camera_position = options.positions.front();
      // Dark levels four times longer, for the black level's sake; full white stays within range at 1.
      c.exposure = level <= 96 ? 4.0 : 1.0;
      c.show = Shown(system, layer, LevelFile(layer.name, level));
      plan.captures.push_back(c);
    }
  return plan;
}

std::vector<uint8_t> PatternImage(const DisplaySystem& system, const CapturePlan& plan, const std::string& panel,
                                  const std::string& name) {
  const PanelSpec& p = LayerNamed(system, panel).panel;
  const auto cols = p.resolution_cols, rows = p.resolution_rows;
  std::vector<uint8_t> image(static_cast<size_t>(cols * rows), 0);
  auto active = [&](auto value) {
    for (int64_t r = p.active_top; r < p.active_top + p.active_rows; ++r)
      for (int64_t c = p.active_left; c < p.active_left + p.active_cols; ++c)
        image[static_cast<size_t>(r * cols + c)] = value(c, r);
  };
  if (name == ChessboardFile(panel)) {
    const Chessboard* board = plan.chessboard(panel);
    if (!board) throw Error("the capture plan has no chessboard for panel \"" + panel + "\"");
    active([&](int64_t c, int64_t r) { return board->dark(c, r) ? uint8_t{0} : uint8_t{255}; });
  } else if (name == WhiteFile(panel)) {
    active([](int64_t, int64_t) { return uint8_t{255}; });
  } else if (name == BlackFile(panel)) {
  } else {
    const std::string prefix = panel + "_level_";
    const bool digits =
        name.size() == prefix.size() + 7 && std::all_of(name.begin() + static_cast<std::ptrdiff_t>(prefix.size()),
                                                        name.begin() + static_cast<std::ptrdiff_t>(prefix.size() + 3),
                                                        [](char ch) { return ch >= '0' && ch <= '9'; });
    if (name.rfind(prefix, 0) != 0 || !digits || name.substr(prefix.size() + 3) != ".png")
      throw Error("\"" + name + "\" is not a pattern of panel \"" + panel + "\"");
    const int level = std::stoi(name.substr(prefix.size(), 3));
    if (level > 255) throw Error("\"" + name + "\": levels are 8-bit, 0 to 255");
    active([level](int64_t, int64_t) { return static_cast<uint8_t>(level); });
  }
  return image;
}

std::vector<std::pair<std::string, std::string>> PatternFiles(const CapturePlan& plan) {
  std::vector<std::pair<std::string, std::string>> out;
  std::set<std::string> seen;
  const std::string folder = std::string(kPatternFolder) + "/";
  for (const PlannedCapture& c : plan.captures)
    for (const auto& [panel, file] : c.show)
      if (seen.insert(file).second)
        out.emplace_back(panel, file.rfind(folder, 0) == 0 ? file.substr(folder.size()) : file);
  return out;
}

ordered_json CapturePlanToJson(const CapturePlan& plan) {
  ordered_json doc;
  doc["format"] = kCapturesFormat;
  doc["description"] = plan.description;
  doc["response"] = plan.response;
  if (plan.camera) doc["camera"] = CameraIntrinsicsToJson(*plan.camera);
  ordered_json boards = ordered_json::object();
  for (const Chessboard& b : plan.chessboards)
    boards[b.panel] = {{"squares", {b.squares_x, b.squares_y}},
                       {"square_pixels", b.square_pixels},
                       {"top_left_pixel", {b.left, b.top}}};
  doc["chessboards"] = boards;
  ordered_json captures = ordered_json::array();
  for (const PlannedCapture& c : plan.captures) {
    ordered_json j;
    j["photo"] = c.photo;
    j["pattern"] = c.kind == CaptureKind::kChessboard ? "chessboard" : "luminance";
    j["panel"] = c.panel;
    if (c.kind == CaptureKind::kLuminance) j["level"] = c.level;
    j["camera_position"] = {Millimeters(c.camera_position[0]), Millimeters(c.camera_position[1])};
    j["exposure"] = c.exposure;
    ordered_json show = ordered_json::object();
    for (const auto& [panel, file] : c.show) show[panel] = file;
    j["show"] = show;
    captures.push_back(j);
  }
  doc["captures"] = captures;
  return doc;
}

CapturePlan ParseCapturePlan(const json& document, const std::string& file) {
  CapturePlan plan;
  Params top(document, {file, ""});
  const std::string format = top.string("format");
  if (format != kCapturesFormat)
    top.fail("format",
             "unknown capture plan format \"" + format + "\"; this layerlab reads \"" + kCapturesFormat + "\"");
  plan.description = top.string("description", "");
  plan.response = top.string("response", "linear");
  if (!ResponseExponent(plan.response))
    top.fail("response", "expected \"linear\" or \"gamma G\" (value^G is linear light, G finite and above 0), got \"" +
                             plan.response + "\"");
  top.mark_read("camera");
  if (top.has("camera")) plan.camera = ReadCameraIntrinsics(top.object("camera"));
  Params boards = top.object("chessboards");
  const json& boards_json = top.raw("chessboards");
  for (auto it = boards_json.begin(); it != boards_json.end(); ++it) {
    boards.mark_read(it.key());
    Params b = boards.object(it.key());
    Chessboard board;
    board.panel = it.key();
    const auto squares = b.integer_pair("squares", 1, 1000);
    if (std::string why = ChessboardSquaresProblem(squares[0], squares[1]); !why.empty()) b.fail("squares", why);
    board.squares_x = static_cast<int>(squares[0]);
    board.squares_y = static_cast<int>(squares[1]);
    board.square_pixels = static_cast<int>(b.integer("square_pixels", 1, 100000));
    const auto top_left = b.integer_pair("top_left_pixel", 0, int64_t{1} << 40);
    board.left = top_left[0];
    board.top = top_left[1];
    b.check_all_read();
    plan.chessboards.push_back(board);
  }
  boards.check_all_read();
  const json& captures = top.raw("captures");
  if (!captures.is_array()) top.fail("captures", "expected an array of captures, got " + JsonKindName(captures));
  for (size_t i = 0; i < captures.size(); ++i) {
    Params c(captures[i], top.where("captures").child(i));
    PlannedCapture p;
    p.photo = c.string("photo");
    // Photographs lie in the captures folder itself: `photograph` writes them there.
    if (p.photo.empty() || p.photo == "." || p.photo == ".." || p.photo.find('/') != std::string::npos ||
        p.photo.find('\0') != std::string::npos)
      c.fail("photo", "expected a file name in the captures folder (no folders, no \"..\"), got \"" + p.photo + "\"");
    const std::string pattern = c.choice("pattern", {"chessboard", "luminance"}, "chessboard");
    p.kind = pattern == "chessboard" ? CaptureKind::kChessboard : CaptureKind::kLuminance;
    p.panel = c.string("panel");
    if (p.kind == CaptureKind::kLuminance) p.level = static_cast<int>(c.integer("level", 0, 255));
    p.camera_position = c.quantity_pair("camera_position", Dimension::kLength, {0, 0});
    p.exposure = c.quantity("exposure", Dimension::kFraction, 1.0);
    if (!(p.exposure > 0)) c.fail("exposure", "the exposure must be positive");
    c.mark_read("show");
    if (c.has("show")) {
      const json& show = c.raw("show");
      if (!show.is_object()) c.fail("show", "expected an object: panel name -> pattern file");
      for (auto it = show.begin(); it != show.end(); ++it) {
        if (!it->is_string()) throw Error(c.where("show").child(it.key()), "expected the pattern file's name");
        p.show.emplace_back(it.key(), it->get<std::string>());
      }
    }
    if (p.kind == CaptureKind::kChessboard && !plan.chessboard(p.panel))
      c.fail("panel", "no chessboard is described for panel \"" + p.panel + "\" (see \"chessboards\")");
    c.check_all_read();
    plan.captures.push_back(p);
  }
  top.check_all_read();
  return plan;
}

CapturePlan ReadCapturePlanFile(const std::string& path) { return ParseCapturePlan(ReadJsonFile(path), path); }

}  // namespace layerlab

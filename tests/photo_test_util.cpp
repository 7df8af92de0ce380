#include "layerlab/tests/photo_test_util.h"

#include <unistd.h>

#include <filesystem>

#include "layerlab/framework/error.h"
#include "layerlab/tests/test_util.h"

namespace layerlab::testing {

DisplaySystem Example(const std::string& name) { return CompileJson(ReadExample(name), ExamplePath(name)); }

std::string FreshFolder(const std::string& name) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("layerlab_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder.string();
}

PhotoCamera TestCamera() {
  PhotoCamera c;
  c.intrinsics = {760, 760, 359.5, 209.5, -0.05, 0, std::nullopt};
  c.width = 720;
  c.height = 420;
  c.aperture_m = 1e-3;
  c.focus_diopters = 1.3;
  c.white = 0.5;
  c.full_well = 20000;
  c.read_noise = 0.001;
  c.supersampling = 3;
  c.seed = 26;
  return c;
}

DisplaySystem Built(const DisplaySystem& designed, const std::vector<PanelTruth>& truth,
                    const std::vector<OpticTruth>& optics) {
  nlohmann::json scene = BuiltScene(designed, truth, optics);
  for (const PanelTruth& t : truth)
    if (t.gamma > 0) {
      ElementNamed(scene, t.name)["gamma"] = t.gamma;
      ElementNamed(scene, t.name)["black_level"] = t.black_level;
    }
  return CompileJson(scene, designed.file);
}

const VirtualLayer& Layer(const DisplaySystem& s, const std::string& name) {
  for (const VirtualLayer& l : s.layers)
    if (l.name == name) return l;
  throw Error("no layer " + name);
}

const PlannedCapture& ChessboardCapture(const CapturePlan& plan, const std::string& panel, size_t position) {
  size_t k = 0;
  for (const PlannedCapture& c : plan.captures)
    if (c.kind == CaptureKind::kChessboard && c.panel == panel && k++ == position) return c;
  throw Error("no chessboard capture of " + panel);
}

Photo AsPhoto(const Image& image) { return {image.width, image.height, image.pixels}; }

std::vector<std::array<double, 2>> TrueCorners(const DisplaySystem& built, const CapturePlan& plan,
                                               const PlannedCapture& capture, const CameraIntrinsics& camera) {
  const Chessboard& board = *plan.chessboard(capture.panel);
  std::vector<std::array<double, 2>> out;
  for (int b = 0; b < board.corners_y(); ++b)
    for (int a = 0; a < board.corners_x(); ++a) {
      const auto pixel = board.corner(a, b);
      const auto angle =
          ImagedMarker(built, Layer(built, capture.panel), pixel[0], pixel[1], {}, capture.camera_position);
      out.push_back(CameraPixelFromAngle(camera, angle[0], angle[1]));
    }
  return out;
}

PlanOptions TestPlan() {
  PlanOptions o;
  o.levels = {0, 32, 64, 96, 128, 160, 192, 224, 255};
  return o;
}

uint32_t Crc32(const std::string& bytes) {
  uint32_t crc = 0xffffffffu;
  for (unsigned char b : bytes) {
    crc ^= b;
    for (int k = 0; k < 8; ++k) crc = crc & 1 ? (crc >> 1) ^ 0xedb88320u : crc >> 1;
  }
  return ~crc;
}

std::string BigEndian(uint32_t v, int bytes) {
  std::string s;
  for (int k = bytes - 1; k >= 0; --k) s.push_back(static_cast<char>(v >> (8 * k)));
  return s;
}

}  // namespace layerlab::testing

// Calibration from photographs (issue 26, docs/calibration.md): capture plan ->
// synthetic photographs of a display as built -> detect -> fit, against the
// known truth; and each kind of failed photograph reported with its reason.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <sys/stat.h>
#include <unistd.h>

#include "layerlab/calibration/calibration.h"
#include "layerlab/calibration/capture_plan.h"
#include "layerlab/calibration/photo_detection.h"
#include "layerlab/calibration/synthetic_measurements.h"
#include "layerlab/calibration/synthetic_photo.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/tests/calibration_test_util.h"
#include "layerlab/tests/photo_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::AsPhoto;
using testing::BigEndian;
using testing::Built;
using testing::ChessboardCapture;
using testing::Crc32;
using testing::Example;
using testing::FreshFolder;
using testing::Layer;
using testing::PanelTruth;
using testing::TestCamera;
using testing::TestPlan;
using testing::TrueCorners;

double RmsPixels(const FoundCorners& found, const std::vector<std::array<double, 2>>& truth) {
  double sum = 0;
  for (size_t k = 0; k < truth.size(); ++k)
    sum += std::pow(found.camera_pixels[k][0] - truth[k][0], 2) + std::pow(found.camera_pixels[k][1] - truth[k][1], 2);
  return std::sqrt(sum / static_cast<double>(truth.size()));
}

TEST(CapturePlanTest, ChessboardsFitTheActiveRegionsAndTheFileRoundTrips) {
  const DisplaySystem designed = Example("paper_prototype.json");
  const CapturePlan plan = PlanCaptures(designed, TestPlan());
  ASSERT_EQ(plan.chessboards.size(), 4u);
  for (const Chessboard& b : plan.chessboards) {
    const PanelSpec& p = Layer(designed, b.panel).panel;
    EXPECT_EQ(b.square_pixels, 25);  // min(400 / 12, 200 / 8)
    EXPECT_GE(b.left - p.active_left, b.square_pixels);
    EXPECT_GE(b.top - p.active_top, b.square_pixels);
    EXPECT_LE(b.left + b.squares_x * b.square_pixels + b.square_pixels, p.active_left + p.active_cols);
    const std::vector<uint8_t> image = PatternImage(designed, plan, b.panel, b.panel + "_chessboard.png");
    EXPECT_EQ(image[static_cast<size_t>(b.top * p.resolution_cols + b.left)], 0);  // the top-left square is dark
    EXPECT_EQ(image[static_cast<size_t>(b.top * p.resolution_cols + b.left + b.square_pixels)], 255);
    EXPECT_EQ(image[0], 0);  // outside the active region
  }
  // 4 panels x 3 positions of chessboards, 4 x 9 luminance steps.
  EXPECT_EQ(plan.captures.size(), 12u + 36u);
  // While rear_a is measured its branch's front panel is white, the other branch black.
  const PlannedCapture& c = ChessboardCapture(plan, "rear_a");
  std::map<std::string, std::string> show(c.show.begin(), c.show.end());
  EXPECT_EQ(show["front_a"], "patterns/front_a_white.png");
  EXPECT_EQ(show["front_b"], "patterns/front_b_black.png");
  const nlohmann::json written = nlohmann::json::parse(CapturePlanToJson(plan).dump());
  const CapturePlan again = ParseCapturePlan(written, "captures.json");
  EXPECT_TRUE(nlohmann::json(CapturePlanToJson(again)) == written);
  nlohmann::json bad = nlohmann::json::parse(CapturePlanToJson(plan).dump());
  bad["captures"][3]["exposur"] = 2;
  try {
    ParseCapturePlan(bad, "captures.json");
    FAIL() << "a misspelled key was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("captures.json: /captures/3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("exposure"), std::string::npos) << e.what();
  }
}

TEST(PanelGeometryTest, PixelAndRayMapsInvertEachOther) {
  const DisplaySystem built = Built(Example("per_branch_magnifiers.json"), testing::PerBranchTruth());
  for (const VirtualLayer& layer : built.layers) {
    const auto point = PanelPoint(layer, 17.25, 9.5);
    const auto back = PanelPixelAt(layer, point);
    EXPECT_NEAR(back[0], 17.25, 1e-9) << layer.name;
    EXPECT_NEAR(back[1], 9.5, 1e-9) << layer.name;
    const std::array<double, 2> position = {1.5e-3, -2e-3};
    const auto slope = RaySlopeTo(layer, point, position);
    const auto met = PanelPointOfRay(layer, position, slope);
    EXPECT_NEAR(met[0], point[0], 1e-12) << layer.name;
    EXPECT_NEAR(met[1], point[1], 1e-12) << layer.name;
  }
}

// Sub-pixel accuracy against the known projection (the built display's optics and the camera).
TEST(PhotoDetectionTest, ChessboardCornersAreFoundToSubPixelAccuracy) {
  const DisplaySystem designed = Example("paper_prototype.json");
  const DisplaySystem built = Built(designed, testing::ExampleTruth());
  const CapturePlan plan = PlanCaptures(designed, TestPlan());
  PhotoCamera quiet = TestCamera();
  quiet.full_well = 0;
  quiet.read_noise = 0;
  const PhotoRenderer clean(quiet), noisy(TestCamera());
  double worst_clean = 0, worst_noisy = 0;
  for (const std::string panel : {"rear_a", "front_b"})
    for (size_t position : {0, 1}) {
      const PlannedCapture& c = ChessboardCapture(plan, panel, position);
      const auto truth = TrueCorners(built, plan, c, quiet.intrinsics);
      const auto predicted = TrueCorners(designed, plan, c, quiet.intrinsics);
      for (const PhotoRenderer* r : {&clean, &noisy}) {
        const CornerSearch found =
            FindChessboardCorners(AsPhoto(r->Render(built, plan, c, 1)), *plan.chessboard(panel), predicted);
        ASSERT_TRUE(found.corners) << panel << ": " << found.reason;
        const double rms = RmsPixels(*found.corners, truth);
        (r == &clean ? worst_clean : worst_noisy) = std::max(r == &clean ? worst_clean : worst_noisy, rms);
      }
    }
  std::printf("corner RMS against the true projection: %.4f px noise-free, %.4f px with noise\n", worst_clean,
              worst_noisy);
  EXPECT_LT(worst_clean, 0.1);
  EXPECT_LT(worst_noisy, 0.15);
}

TEST(PhotoDetectionTest, EachKindOfBadPhotographIsReportedWithItsReason) {
  const DisplaySystem designed = Example("paper_prototype.json");
  const CapturePlan plan = PlanCaptures(designed, TestPlan());
  const PlannedCapture& c = ChessboardCapture(plan, "rear_a");
  const auto predicted = TrueCorners(designed, plan, c, TestCamera().intrinsics);
  auto reason = [&](const PhotoCamera& camera, const PlannedCapture& capture) {
    const CornerSearch s = FindChessboardCorners(AsPhoto(PhotoRenderer(camera).Render(designed, plan, capture, 2)),
                                                 *plan.chessboard("rear_a"), predicted);
    EXPECT_FALSE(s.corners);
    return s.reason;
  };
  PhotoCamera blurred = TestCamera();
  blurred.aperture_m = 12e-3;
  blurred.focus_diopters = 3.0;  // 2.6 D from rear_a: a blur of 24 px against squares of 30 px
  PhotoCamera noisy = TestCamera();
  noisy.read_noise = 0.15;
  PhotoCamera bright = TestCamera();
  bright.white = 4;
  PlannedCapture blank = c;  // the panel white: no pattern
  for (auto& [panel, file] : blank.show)
    if (panel == "rear_a") file = "patterns/rear_a_white.png";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {reason(blurred, c), "pattern not found: no 9 x 5 chessboard corners (the photograph is out of focus"},
      {reason(noisy, c), "pattern not found: no 9 x 5 chessboard corners (the photograph is too noisy"},
      {reason(bright, c), "overexposed: "},
      {reason(TestCamera(), blank), "pattern not found: no 9 x 5 chessboard corners (the photograph shows no pattern"}};
  for (const auto& [said, expected] : cases) {
    std::printf("%s\n", said.c_str());
    EXPECT_EQ(said.rfind(expected, 0), 0u) << said;
  }
}

// Another plan's board is named as such, not "out of focus" or "not in view whole": 8 x 5 squares where the plan
// has 10 x 6, and 10 x 6 where it has 8 x 5 (a board wider than the predicted one).
TEST(PhotoDetectionTest, AChessboardOfOtherSquareCountsIsNamedAsSuch) {
  const DisplaySystem designed = Example("paper_prototype.json");
  auto plan_of = [&](int x, int y) {
    PlanOptions o = TestPlan();
    o.squares_x = x;
    o.squares_y = y;
    return PlanCaptures(designed, o);
  };
  const CapturePlan ten_by_six = plan_of(10, 6), eight_by_five = plan_of(8, 5);
  auto reason = [&](const CapturePlan& planned, const CapturePlan& shown) {
    const PlannedCapture& c = ChessboardCapture(planned, "rear_a");
    const auto predicted = TrueCorners(designed, planned, c, TestCamera().intrinsics);
    const Photo photo =
        AsPhoto(PhotoRenderer(TestCamera()).Render(designed, shown, ChessboardCapture(shown, "rear_a"), 2));
    const CornerSearch s = FindChessboardCorners(photo, *planned.chessboard("rear_a"), predicted);
    EXPECT_FALSE(s.corners);
    return s.reason;
  };
  const std::string narrower = reason(ten_by_six, eight_by_five), wider = reason(eight_by_five, ten_by_six);
  EXPECT_EQ(narrower.rfind("wrong chessboard: the photograph shows one of 8 x 5 squares (its 7 x 4 inner corners "
                           "found), the capture plan's has 10 x 6",
                           0),
            0u)
      << narrower;
  EXPECT_EQ(wider.rfind("wrong chessboard: the photograph shows one of 10 x 6 squares (its 9 x 5 inner corners "
                        "found), the capture plan's has 8 x 5",
                        0),
            0u)
      << wider;
}

// Boards OpenCV cannot take (fewer than 3 inner corners a side) or could find turned (square grids) are refused
// when planned and when read from captures.json.
TEST(CapturePlanTest, ChessboardsOpenCvCannotTakeAreRefused) {
  const DisplaySystem designed = Example("paper_prototype.json");
  for (const auto& [x, y] : std::vector<std::pair<int, int>>{{4, 3}, {3, 6}, {6, 6}, {2147483647, 6}}) {
    PlanOptions o = TestPlan();
    o.squares_x = x;
    o.squares_y = y;
    EXPECT_THROW(PlanCaptures(designed, o), Error) << x << " x " << y;
    nlohmann::json doc = CapturePlanToJson(PlanCaptures(designed, TestPlan()));
    doc["chessboards"]["rear_a"]["squares"] = {x, y};
    try {
      ParseCapturePlan(doc, "captures.json");
      ADD_FAILURE() << x << " x " << y << " read";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("/chessboards/rear_a/squares"), std::string::npos) << e.what();
    }
  }
  nlohmann::json doc = CapturePlanToJson(PlanCaptures(designed, TestPlan()));
  for (const char* photo : {"../outside.exr", "/tmp/x.exr", "sub/x.exr", ""}) {
    doc["captures"][0]["photo"] = photo;
    EXPECT_THROW(ParseCapturePlan(doc, "captures.json"), Error) << photo;
  }
}

void WriteBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// A PNG of a valid signature and header (CRC included) that declares `width` x `height` 16-bit RGBA pixels, and
// nothing after it.
std::string PngHeaderOnly(uint32_t width, uint32_t height) {
  const std::string ihdr = "IHDR" + BigEndian(width) + BigEndian(height) + std::string{16, 6, 0, 0, 0};
  return std::string("\x89PNG\r\n\x1a\n", 8) + BigEndian(13) + ihdr + BigEndian(Crc32(ihdr));
}

// One unusable photograph of each kind is named with its reason, and the good one is used: a FIFO named .png
// (which blocked OpenCV's open forever), a PNG declaring 30000 x 30000 pixels, a truncated PNG, an EXR with a
// NaN pixel, a folder.
TEST(PhotoDetectionTest, EachUnusablePhotographIsNamedAndTheOthersGoOn) {
  const DisplaySystem designed = Example("paper_prototype.json");
  CapturePlan plan = PlanCaptures(designed, TestPlan());
  const PlannedCapture good = ChessboardCapture(plan, "rear_a");
  plan.camera = TestCamera().intrinsics;
  const std::string folder = FreshFolder("unusable_photos");
  WriteExr(folder + "/" + good.photo, PhotoRenderer(TestCamera()).Render(designed, plan, good, 1),
           ExrCompression::kNone);
  const std::map<std::string, std::string> expected = {
      {"fifo.png", "is a FIFO"},
      {"huge.png", "the PNG declares 30000 x 30000 pixels; the limit is"},
      {"truncated.png", "truncated PNG file"},
      {"nan.exr", "pixel (row 1, col 2) channel Y is NaN"},
      {"folder.png", "is a folder"}};
  plan.captures = {good};
  for (const auto& [name, reason] : expected) {
    PlannedCapture c = good;
    c.photo = name;
    plan.captures.push_back(c);
  }
  ASSERT_EQ(::mkfifo((folder + "/fifo.png").c_str(), 0600), 0);
  std::filesystem::create_directory(folder + "/folder.png");
  WriteBytes(folder + "/huge.png", PngHeaderOnly(30000, 30000));
  WriteBytes(folder + "/truncated.png", PngHeaderOnly(300, 200).substr(0, 20));
  Image nan = PhotoRenderer(TestCamera()).Render(designed, plan, good, 1);
  nan.pixels[1 * nan.width + 2] = NAN;
  WriteExr(folder + "/nan.exr", nan, ExrCompression::kNone);

  const Detection d = DetectCaptures(folder, plan, designed, std::nullopt);
  std::filesystem::remove_all(folder);
  EXPECT_EQ(d.corners, 45u);
  ASSERT_EQ(d.failures.size(), expected.size());
  for (const PhotoFailure& f : d.failures) {
    ASSERT_TRUE(expected.count(f.photo)) << f.photo;
    EXPECT_NE(f.reason.find(expected.at(f.photo)), std::string::npos) << f.photo << ": " << f.reason;
    EXPECT_EQ(f.reason.find("internal error"), std::string::npos) << f.reason;
  }
}

// The whole loop on one display: the plan's photographs of it as built, written
// and read back as files, detected and fitted; every placement within 4
// reported standard deviations of the truth, the residual at the noise floor
// the corners' scatter implies.
void ExpectLoopRecovers(const DisplaySystem& designed, const DisplaySystem& built, const PlanOptions& plan_options,
                        const CalibrationOptions& fit, const std::string& folder_name, bool luminance) {
  CapturePlan plan = PlanCaptures(designed, plan_options);
  if (!luminance)
    std::erase_if(plan.captures, [](const PlannedCapture& c) { return c.kind == CaptureKind::kLuminance; });
  const PhotoCamera camera = TestCamera();
  plan.camera = camera.intrinsics;
  const PhotoRenderer renderer(camera);
  const std::string folder = FreshFolder(folder_name);
  for (size_t k = 0; k < plan.captures.size(); ++k)
    WriteExr(folder + "/" + plan.captures[k].photo, renderer.Render(built, plan, plan.captures[k], k),
             ExrCompression::kNone);
  const Detection d = DetectCaptures(folder, plan, designed, std::nullopt);
  std::filesystem::remove_all(folder);
  for (const PhotoFailure& f : d.failures) ADD_FAILURE() << f.photo << ": " << f.reason;
  ASSERT_GT(d.corners, 0u);

  // The noise floor: the detected corners' error against where the built display truly shows them
  // (the sensor's noise, the sampling's and the detector's own bias together), per marker, both axes.
  double error_sq = 0;
  size_t markers = 0;
  for (const Capture& capture : d.measurements.captures)
    for (const PanelMarkers& panel : capture.panels)
      for (const MarkerObservation& m : panel.markers) {
        const auto truth = ImagedMarker(built, Layer(built, panel.panel), m.col, m.row, {}, capture.camera_position);
        error_sq += std::pow(m.angle_x - truth[0], 2) + std::pow(m.angle_y - truth[1], 2);
        ++markers;
      }
  const double floor = std::sqrt(error_sq / static_cast<double>(markers));
  // The sensor noise's share: the scatter of one board's corners over photographs that differ in their noise alone.
  const PlannedCapture& c = ChessboardCapture(plan, designed.layers.front().name);
  const auto predicted = TrueCorners(designed, plan, c, camera.intrinsics);
  std::vector<FoundCorners> repeats;
  for (uint64_t seed = 100; seed < 104; ++seed) {
    const CornerSearch s =
        FindChessboardCorners(AsPhoto(renderer.Render(built, plan, c, seed)), *plan.chessboard(c.panel), predicted);
    ASSERT_TRUE(s.corners) << s.reason;
    repeats.push_back(*s.corners);
  }
  double variance = 0;  // per axis, px^2
  const size_t n = repeats.front().camera_pixels.size();
  for (size_t k = 0; k < n; ++k)
    for (int axis = 0; axis < 2; ++axis) {
      double mean = 0, sq = 0;
      for (const FoundCorners& f : repeats) mean += f.camera_pixels[k][axis] / repeats.size();
      for (const FoundCorners& f : repeats) sq += std::pow(f.camera_pixels[k][axis] - mean, 2);
      variance += sq / (repeats.size() - 1) / (2.0 * n);
    }

  CalibratedDisplay display;
  const CalibrationReport report = Calibrate(designed, d.measurements, fit, &display);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  std::printf(
      "%s: %zu corners, residual %.4f arcmin per marker (%.4f px); the corners' error against the truth "
      "%.4f arcmin (%.4f px); their scatter over the sensor's noise alone %.4f px per axis\n",
      designed.file.c_str(), d.corners, report.marker_rms_after_rad / testing::kArcmin,
      report.marker_rms_after_rad * camera.intrinsics.fx, floor / testing::kArcmin, floor * camera.intrinsics.fx,
      std::sqrt(variance));
  // The fit leaves what the measurements' errors leave (less the few degrees of freedom it fits), no more.
  EXPECT_GT(report.marker_rms_after_rad, 0.8 * floor);
  EXPECT_LT(report.marker_rms_after_rad, 1.05 * floor);
  for (const VirtualLayer& layer : built.layers) {
    const std::map<std::string, double> truth = {{"distance", layer.panel_distance_m},
                                                 {"offset_x", layer.panel.eye_from_panel_m[0]},
                                                 {"offset_y", layer.panel.eye_from_panel_m[1]},
                                                 {"rotation", layer.panel.rotation_rad}};
    for (const auto& [quantity, value] : truth) {
      const ParameterEstimate* p = report.find(layer.name, quantity);
      ASSERT_NE(p, nullptr) << layer.name << " " << quantity;
      ASSERT_TRUE(p->std_dev) << layer.name << " " << quantity;
      std::printf("  %-8s %-9s true %+.6g fitted %+.6g sd %.2g: %+.1f sd\n", layer.name.c_str(), quantity.c_str(),
                  value, p->value, *p->std_dev, (p->value - value) / *p->std_dev);
      EXPECT_LE(std::abs(p->value - value), testing::kSigmas * *p->std_dev) << layer.name << " " << quantity;
    }
    if (luminance)
      for (const auto& [quantity, value] :
           std::map<std::string, double>{{"gamma", layer.panel.gamma}, {"black_level", layer.panel.black_level}}) {
        const ParameterEstimate* p = report.find(layer.name, quantity);
        ASSERT_NE(p, nullptr) << layer.name << " " << quantity;
        ASSERT_TRUE(p->std_dev) << layer.name << " " << quantity;
        std::printf("  %-8s %-11s true %.5g fitted %.5g sd %.2g: %+.1f sd\n", layer.name.c_str(), quantity.c_str(),
                    value, p->value, *p->std_dev, (p->value - value) / *p->std_dev);
        EXPECT_LE(std::abs(p->value - value), testing::kSigmas * *p->std_dev) << layer.name << " " << quantity;
      }
  }
}

TEST(PhotoCalibrationLoopTest, PaperPrototypeFromPhotographs) {
  const DisplaySystem designed = Example("paper_prototype.json");
  ExpectLoopRecovers(designed, Built(designed, testing::ExampleTruth()), TestPlan(), CalibrationOptions{},
                     "photo_loop_paper", true);
}

TEST(PhotoCalibrationLoopTest, PerBranchMagnifiersFromPhotographs) {
  const DisplaySystem designed = Example("per_branch_magnifiers.json");
  PlanOptions plan = TestPlan();
  plan.squares_x = 8;  // 80 x 40 pixel panels: squares of 4 pixels
  plan.squares_y = 6;
  plan.positions = {{0.0, 0.0}, {-3e-3, 0.0}, {3e-3, 0.0}, {0.0, -3e-3}, {0.0, 3e-3}};
  CalibrationOptions fit;
  fit.lens_gaps = FitChoice::kFit;
  ExpectLoopRecovers(designed, Built(designed, testing::PerBranchTruth(), testing::PerBranchOptics()), plan, fit,
                     "photo_loop_per_branch", false);
}

}  // namespace
}  // namespace layerlab

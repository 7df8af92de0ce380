// The wrong photographs `detect` catches (issue 43): a mirrored or turned
// board, a repeated capture (every photograph kept), a PNG where the plan
// names EXR (and a PNG saved as .exr), a too-noisy photograph named as such.
// Photographs from the project's renderer (calibration/synthetic_photo.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>

#include "layerlab/calibration/measurements.h"
#include "layerlab/calibration/photo_detection.h"
#include "layerlab/calibration/photo_files.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/tests/photo_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::AsPhoto;
using testing::BigEndian;
using testing::ChessboardCapture;
using testing::Crc32;
using testing::Example;
using testing::FreshFolder;
using testing::TestCamera;
using testing::TestPlan;
using testing::TrueCorners;

CapturePlan PlanOf(const DisplaySystem& designed, int squares_x, int squares_y) {
  PlanOptions o = TestPlan();
  o.squares_x = squares_x;
  o.squares_y = squares_y;
  CapturePlan plan = PlanCaptures(designed, o);
  plan.camera = TestCamera().intrinsics;
  return plan;
}

// The design with rear_a mounted otherwise: "reversed" (mirrored about its vertical axis) and/or turned in
// its plane by `turn` rad.
DisplaySystem RearAMounted(const DisplaySystem& designed, bool reversed, double turn) {
  nlohmann::json scene = testing::BuiltScene(designed, {{"rear_a", 0, 0, 0, turn, 0, 0, 0}});
  testing::ElementNamed(scene, "rear_a")["reversed"] = reversed;
  return testing::CompileJson(scene, designed.file);
}

// rear_a's board as `built` shows it, searched for as the design predicts it.
CornerSearch SearchRearA(const DisplaySystem& designed, const DisplaySystem& built, const CapturePlan& plan) {
  const PlannedCapture& c = ChessboardCapture(plan, "rear_a");
  const Photo photo = AsPhoto(PhotoRenderer(TestCamera()).Render(built, plan, c, 3));
  return FindChessboardCorners(photo, *plan.chessboard("rear_a"),
                               TrueCorners(designed, plan, c, TestCamera().intrinsics));
}

bool StartsWith(const std::string& s, const std::string& head) { return s.rfind(head, 0) == 0; }

// The board is centred in its panel, so mirrored or turned its corners lie where the design predicts them and
// only its squares' colours tell. 10 x 6 squares (both even): a mirror either way is refused. 10 x 5: a mirror
// left to right and a 180-degree turn. 9 x 6: a mirror top to bottom (reversed and turned) and a turn. The same
// board mounted as designed is found (each plan's control).
TEST(PhotoDetectionTest, AMirroredOrTurnedBoardIsRefusedNamingIt) {
  const DisplaySystem designed = Example("paper_prototype.json");
  const double half_turn = std::numbers::pi;
  struct Case {
    int x, y;
    bool reversed;
    double turn;
    std::string reason;  // its start
  };
  const std::vector<Case> cases = {
      {10, 6, true, 0,
       "mirrored board: its dark corner squares are at the top right and bottom left where the design "
       "puts them at the top left and bottom right"},
      {10, 6, true, half_turn, "mirrored board: its dark corner squares are at the top right and bottom left"},
      {10, 5, true, 0,
       "mirrored or turned board: its dark corner squares are on the right where the design puts "
       "them on the left"},
      {10, 5, false, half_turn, "mirrored or turned board: its dark corner squares are on the right"},
      {9, 6, true, half_turn,
       "mirrored or turned board: its dark corner squares are at the bottom where the design "
       "puts them at the top"},
      {9, 6, false, half_turn, "mirrored or turned board: its dark corner squares are at the bottom"},
  };
  for (const Case& k : cases) {
    const CapturePlan plan = PlanOf(designed, k.x, k.y);
    const std::string label = std::to_string(k.x) + " x " + std::to_string(k.y) + (k.reversed ? " reversed" : "") +
                              (k.turn != 0 ? " turned" : "");
    const CornerSearch as_designed = SearchRearA(designed, designed, plan);
    EXPECT_TRUE(as_designed.corners) << label << ", as designed: " << as_designed.reason;
    const CornerSearch s = SearchRearA(designed, RearAMounted(designed, k.reversed, k.turn), plan);
    EXPECT_FALSE(s.corners) << label;
    EXPECT_TRUE(StartsWith(s.reason, k.reason)) << label << ": " << s.reason;
    EXPECT_NE(s.reason.find("was this photograph taken of another panel, or is the panel mounted"), std::string::npos)
        << s.reason;
  }
}

// A photograph of another panel saved under rear_a's name: rear_b (the half mirror's reflected branch) and
// front_a (mounted reversed) show the same board mirrored against rear_a's, 4 % and 8 % larger (their virtual
// depths differ), centred in the same place; refused as mirrored. rear_a's own photograph is found.
TEST(PhotoDetectionTest, APhotographOfAnotherPanelThatMirrorsItIsRefused) {
  const DisplaySystem designed = Example("paper_prototype.json");
  const CapturePlan plan = PlanOf(designed, 10, 6);
  const PlannedCapture& rear_a = ChessboardCapture(plan, "rear_a");
  const auto predicted = TrueCorners(designed, plan, rear_a, TestCamera().intrinsics);
  for (const std::string shown : {"rear_a", "rear_b", "front_a"}) {
    const Photo photo = AsPhoto(PhotoRenderer(TestCamera()).Render(designed, plan, ChessboardCapture(plan, shown), 5));
    const CornerSearch s = FindChessboardCorners(photo, *plan.chessboard("rear_a"), predicted);
    if (shown == "rear_a") {
      EXPECT_TRUE(s.corners) << s.reason;
    } else {
      EXPECT_FALSE(s.corners) << shown;
      EXPECT_TRUE(StartsWith(s.reason, "mirrored board: ")) << shown << ": " << s.reason;
    }
  }
}

// A board of odd counts both ways reads the same all four ways: detect warns once per such board photographed.
TEST(PhotoDetectionTest, ABoardWhoseColoursCannotShowItsOrientationIsWarnedOf) {
  const DisplaySystem designed = Example("paper_prototype.json");
  for (const auto& [x, y, warned] : std::vector<std::tuple<int, int, bool>>{{9, 5, true}, {10, 5, false}}) {
    CapturePlan plan = PlanOf(designed, x, y);
    std::erase_if(plan.captures, [](const PlannedCapture& c) { return c.panel != "rear_a"; });
    for (PlannedCapture& c : plan.captures) c.photo = "absent_" + c.photo;  // named as missing, not read
    const std::string folder = FreshFolder("orientation_warning");
    const Detection d = DetectCaptures(folder, plan, designed, std::nullopt);
    std::filesystem::remove_all(folder);
    ASSERT_EQ(d.warnings.size(), warned ? 1u : 0u) << x << " x " << y;  // rear_a's board, the one photographed
    if (warned) {
      EXPECT_EQ(d.warnings[0].rfind(
                    "panel \"rear_a\": a chessboard of 9 x 5 squares (both odd) reads the same mirrored or turned", 0),
                0u)
          << d.warnings[0];
    }
  }
}

// Two photographs of rear_a's board from one camera position (a repeated capture) and one of front_a: every
// photograph's corners reach the measurements file and are read back from it, each as it was found.
TEST(PhotoDetectionTest, EveryPhotographOfARepeatedCaptureIsKept) {
  const DisplaySystem designed = Example("paper_prototype.json");
  CapturePlan plan = PlanOf(designed, 10, 6);
  PlannedCapture first = ChessboardCapture(plan, "rear_a"), again = first, other = ChessboardCapture(plan, "front_a");
  again.photo = "rear_a_chessboard_0_again.exr";
  plan.captures = {first, other, again};
  const std::string folder = FreshFolder("repeated_capture");
  const PhotoRenderer renderer(TestCamera());
  std::vector<std::array<double, 2>> found_first;  // each photograph's first corner, as found alone
  for (size_t k = 0; k < plan.captures.size(); ++k) {
    const Image image = renderer.Render(designed, plan, plan.captures[k], 10 + k);
    WriteExr(folder + "/" + plan.captures[k].photo, image, ExrCompression::kNone);
    const PlannedCapture& c = plan.captures[k];
    const CornerSearch s = FindChessboardCorners(AsPhoto(image), *plan.chessboard(c.panel),
                                                 TrueCorners(designed, plan, c, TestCamera().intrinsics));
    ASSERT_TRUE(s.corners) << s.reason;
    found_first.push_back(s.corners->camera_pixels.front());
  }
  const Detection d = DetectCaptures(folder, plan, designed, std::nullopt);
  std::filesystem::remove_all(folder);
  EXPECT_TRUE(d.failures.empty());
  EXPECT_EQ(d.corners, 3u * 45u);
  const Measurements read = ParseMeasurements(ParseJson(FormatMeasurements(d.measurements), "m.json"), "m.json");
  EXPECT_EQ(read.marker_count(), 3u * 45u);
  std::multiset<std::string> panels;
  std::vector<std::array<double, 2>> read_first;
  for (const Capture& capture : read.captures) {
    EXPECT_EQ(capture.camera_position, first.camera_position);
    for (const PanelMarkers& p : capture.panels) {
      panels.insert(p.panel);
      EXPECT_TRUE(p.detection_noise) << p.panel;  // each photograph's own
      read_first.push_back(*p.markers.front().camera_pixel);
    }
  }
  EXPECT_EQ(panels, (std::multiset<std::string>{"front_a", "rear_a", "rear_a"}));
  for (const auto& uv : found_first) {
    bool kept = false;
    for (const auto& r : read_first) kept = kept || (std::abs(r[0] - uv[0]) < 1e-4 && std::abs(r[1] - uv[1]) < 1e-4);
    EXPECT_TRUE(kept) << "a photograph's corner (" << uv[0] << ", " << uv[1] << ") is not in the file";
  }
  EXPECT_GT(std::hypot(found_first[0][0] - found_first[2][0], found_first[0][1] - found_first[2][1]), 0)
      << "the two photographs of rear_a should differ by their noise";
}

// --- PNG files, written here with an encoder of their own (stored deflate blocks), not OpenCV's ---

std::string Chunk(const std::string& type, const std::string& data) {
  return BigEndian(static_cast<uint32_t>(data.size())) + type + data + BigEndian(Crc32(type + data));
}

// A gray PNG of `bits` (8 or 16) per sample: value = round(signal^(1/gamma) (2^bits - 1)), the signal linear light.
std::string GrayPng(const Image& image, int bits, double gamma) {
  std::string raw;
  const double full = bits == 16 ? 65535.0 : 255.0;
  for (int r = 0; r < image.height; ++r) {
    raw.push_back(0);  // filter: none
    for (int c = 0; c < image.width; ++c) {
      const double v = std::clamp<double>(image.pixels[static_cast<size_t>(r) * image.width + c], 0, 1);
      raw += BigEndian(static_cast<uint32_t>(std::lround(std::pow(v, 1 / gamma) * full)), bits / 8);
    }
  }
  std::string zlib = "\x78\x01";
  for (size_t at = 0; at < raw.size() || at == 0; at += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - at);
    zlib.push_back(at + n >= raw.size() ? 1 : 0);  // BFINAL, stored
    zlib += {static_cast<char>(n & 0xff), static_cast<char>(n >> 8), static_cast<char>(~n & 0xff),
             static_cast<char>((~n >> 8) & 0xff)};
    zlib += raw.substr(at, n);
  }
  uint32_t a = 1, b = 0;
  for (unsigned char ch : raw) a = (a + ch) % 65521, b = (b + a) % 65521;
  zlib += BigEndian(b << 16 | a);
  const std::string ihdr =
      BigEndian(image.width) + BigEndian(image.height) + std::string{static_cast<char>(bits), 0, 0, 0, 0};
  return std::string("\x89PNG\r\n\x1a\n", 8) + Chunk("IHDR", ihdr) + Chunk("IDAT", zlib) + Chunk("IEND", "");
}

void WriteBytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// The plan names rear_a's photographs .exr (as `calibration-patterns` writes it) and states the response
// "gamma 2.2"; the lab saved: a 16-bit PNG under the PNG's name (read where the .exr is absent, said once), an
// 8-bit PNG saved as .exr (read by its content), and, with --photo-format png, x.png beside an x.exr that is
// not a photograph. Each is used and found where the linear photograph's corners are found.
TEST(PhotoDetectionTest, APngIsReadWhereThePlanNamesExr) {
  const DisplaySystem designed = Example("paper_prototype.json");
  CapturePlan plan = PlanOf(designed, 10, 6);
  plan.response = "gamma 2.2";
  plan.captures = {ChessboardCapture(plan, "rear_a", 0), ChessboardCapture(plan, "rear_a", 1)};
  ASSERT_EQ(plan.captures[0].photo, "rear_a_chessboard_0.exr");
  const std::string folder = FreshFolder("png_for_exr");
  std::vector<Image> images;
  for (size_t k = 0; k < 2; ++k)
    images.push_back(PhotoRenderer(TestCamera()).Render(designed, plan, plan.captures[k], k));
  WriteBytes(folder + "/rear_a_chessboard_0.png", GrayPng(images[0], 16, 2.2));
  WriteBytes(folder + "/rear_a_chessboard_1.exr", GrayPng(images[1], 8, 2.2));
  auto expect_found_as_linear = [&](const Detection& d, const std::string& label) {
    EXPECT_TRUE(d.failures.empty()) << label << ": " << (d.failures.empty() ? "" : d.failures[0].reason);
    ASSERT_EQ(d.corners, 90u) << label;
    for (size_t k = 0; k < 2; ++k) {
      const PlannedCapture& c = plan.captures[k];
      const CornerSearch linear = FindChessboardCorners(AsPhoto(images[k]), *plan.chessboard("rear_a"),
                                                        TrueCorners(designed, plan, c, TestCamera().intrinsics));
      ASSERT_TRUE(linear.corners) << linear.reason;
      double worst = 0;
      const PanelMarkers& got = d.measurements.captures[k].panels[0];
      for (size_t m = 0; m < got.markers.size(); ++m)
        worst = std::max(worst, std::hypot((*got.markers[m].camera_pixel)[0] - linear.corners->camera_pixels[m][0],
                                           (*got.markers[m].camera_pixel)[1] - linear.corners->camera_pixels[m][1]));
      std::printf("%s, photograph %zu: corners within %.4f px of the linear photograph's\n", label.c_str(), k, worst);
      EXPECT_LT(worst, k == 0 ? 0.02 : 0.1) << label << " " << k;  // 16 bits; 8 bits
    }
  };
  const Detection d = DetectCaptures(folder, plan, designed, std::nullopt);
  expect_found_as_linear(d, "auto");
  ASSERT_EQ(d.notes.size(), 2u);
  EXPECT_EQ(d.notes[0],
            "1 photograph was read from another file than the plan names (the plan's is absent; e.g. "
            "rear_a_chessboard_0.png for rear_a_chessboard_0.exr), with the plan's response \"gamma 2.2\" "
            "(captures.json's \"response\" states a PNG's curve)");
  EXPECT_EQ(d.notes[1],
            "1 photograph is not the format its name says and was read by content (e.g. rear_a_chessboard_1.exr is a "
            "PNG file)");

  // --photo-format png reads x.png even where x.exr exists; auto and exr read the x.exr, which is no photograph.
  WriteBytes(folder + "/rear_a_chessboard_0.exr", "not a photograph");
  std::filesystem::rename(folder + "/rear_a_chessboard_1.exr", folder + "/rear_a_chessboard_1.png");
  WriteBytes(folder + "/rear_a_chessboard_1.exr", "not a photograph");
  expect_found_as_linear(DetectCaptures(folder, plan, designed, std::nullopt, {}, PhotoFormat::kPng), "png");
  for (PhotoFormat format : {PhotoFormat::kAuto, PhotoFormat::kExr}) {
    const Detection refused = DetectCaptures(folder, plan, designed, std::nullopt, {}, format);
    ASSERT_EQ(refused.failures.size(), 2u);
    EXPECT_NE(refused.failures[0].reason.find("rear_a_chessboard_0.exr: neither an EXR nor a PNG file"),
              std::string::npos)
        << refused.failures[0].reason;
  }
  std::filesystem::remove_all(folder);
}

// Which file each format reads; nothing is opened, and a dangling link counts as there (and is then named).
TEST(PhotoFilesTest, TheFileReadForEachFormat) {
  const std::string folder = FreshFolder("photo_files");
  WriteBytes(folder + "/a.png", "x");
  WriteBytes(folder + "/b.exr", "x");
  WriteBytes(folder + "/b.png", "x");
  std::filesystem::create_symlink(folder + "/nowhere", folder + "/c.exr");
  WriteBytes(folder + "/c.png", "x");
  struct Case {
    std::string name;
    PhotoFormat format;
    std::string read;
    bool other;
  };
  for (const Case& k : std::vector<Case>{{"a.exr", PhotoFormat::kAuto, "a.png", true},
                                         {"b.exr", PhotoFormat::kAuto, "b.exr", false},
                                         {"b.exr", PhotoFormat::kPng, "b.png", true},
                                         {"a.png", PhotoFormat::kExr, "a.exr", true},
                                         {"c.exr", PhotoFormat::kAuto, "c.exr", false},
                                         {"d.exr", PhotoFormat::kAuto, "d.exr", false},
                                         {"a.tif", PhotoFormat::kAuto, "a.tif", false}}) {
    const PhotoFile f = LocatePhoto(folder, k.name, k.format);
    EXPECT_EQ(f.path, folder + "/" + k.read) << k.name;
    EXPECT_EQ(f.other_name, k.other) << k.name;
  }
  EXPECT_EQ(PhotoFormatFromString("png"), PhotoFormat::kPng);
  EXPECT_FALSE(PhotoFormatFromString("PNG"));
  std::filesystem::remove_all(folder);
}

// A photograph whose noise drowns the pattern pixel by pixel is named too noisy, not "shows no pattern" (as at
// 0.2 before): read noise of 0.15 to 0.25 of full scale against a board whose light squares are at about 0.3
// (white lowered so that the noise does not reach full scale, which would read as overexposed).
TEST(PhotoDetectionTest, ATooNoisyPhotographIsNamedAsSuch) {
  const DisplaySystem designed = Example("paper_prototype.json");
  const CapturePlan plan = PlanOf(designed, 10, 6);
  const PlannedCapture& c = ChessboardCapture(plan, "rear_a");
  const auto predicted = TrueCorners(designed, plan, c, TestCamera().intrinsics);
  for (double read_noise : {0.15, 0.2, 0.25}) {
    PhotoCamera noisy = TestCamera();
    noisy.white = 0.3;
    noisy.read_noise = read_noise;
    const CornerSearch s = FindChessboardCorners(AsPhoto(PhotoRenderer(noisy).Render(designed, plan, c, 4)),
                                                 *plan.chessboard("rear_a"), predicted);
    EXPECT_FALSE(s.corners) << read_noise;
    std::printf("read noise %.2f: %s\n", read_noise, s.reason.c_str());
    EXPECT_TRUE(StartsWith(s.reason, "pattern not found: no 9 x 5 chessboard corners (the photograph is too noisy"))
        << read_noise << ": " << s.reason;
  }
}

}  // namespace
}  // namespace layerlab

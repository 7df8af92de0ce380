#include "layerlab/calibration/camera_capture_plan.h"

#include <cmath>
#include <cstddef>
#include <set>

#include "layerlab/calibration/capture_plan.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

// The largest tilt a plan may ask for: beyond it the squares foreshorten past what the corner finder finds.
constexpr double kMaxTiltDeg = 60;

// One pose of the default sequence: tilts (deg) about the horizontal and vertical axes, the board's center in
// the frame and its width there. Face-on boards are left out on purpose: they cannot tell the focal length from
// the distance. The corners of the frame are visited for the distortion, which grows toward them.
struct PoseTemplate {
  double tilt_x_deg, tilt_y_deg, center_x, center_y, width;
};
constexpr std::array<PoseTemplate, 12> kPoses = {{{25, 0, 0.5, 0.5, 0.7},
                                                  {-25, 0, 0.5, 0.5, 0.7},
                                                  {0, 25, 0.5, 0.5, 0.7},
                                                  {0, -25, 0.5, 0.5, 0.7},
                                                  {20, 20, 0.32, 0.32, 0.45},
                                                  {20, -20, 0.68, 0.32, 0.45},
                                                  {-20, 20, 0.32, 0.68, 0.45},
                                                  {-20, -20, 0.68, 0.68, 0.45},
                                                  {35, 0, 0.5, 0.3, 0.5},
                                                  {-35, 0, 0.5, 0.7, 0.5},
                                                  {0, 35, 0.3, 0.5, 0.5},
                                                  {0, -35, 0.7, 0.5, 0.5}}};

std::string Degrees(double rad) {
  std::string s = FormatFixed(rad * kDegreesPerRadian, 1);
  if (s.size() > 2 && s.substr(s.size() - 2) == ".0") s.resize(s.size() - 2);
  return (s == "-0" ? "0" : s) + " deg";
}

std::string TiltWords(double deg, const char* axis, const char* positive_edge, const char* negative_edge) {
  if (deg == 0) return std::string("square to the camera about its ") + axis + " axis";
  return "turned " + Degrees(std::abs(deg) * kRadiansPerDegree) + " about its " + axis + " axis (" +
         (deg > 0 ? positive_edge : negative_edge) + " edge away from the camera)";
}

std::string PlaceWords(double x, double y) {
  const char* row = y < 0.4 ? "upper " : y > 0.6 ? "lower " : "";
  const char* col = x < 0.4 ? "left" : x > 0.6 ? "right" : "";
  if (*row == 0 && *col == 0) return "the middle of the frame";
  if (*col == 0) return std::string(row) + "middle of the frame";
  return std::string("the ") + row + col + " part of the frame";
}

std::string Advice(const PlannedBoardPhoto& p) {
  return "the board " + TiltWords(p.tilt_rad[0] * kDegreesPerRadian, "horizontal", "top", "bottom") + " and " +
         TiltWords(p.tilt_rad[1] * kDegreesPerRadian, "vertical", "right", "left") + "; its center in " +
         PlaceWords(p.center_in_frame[0], p.center_in_frame[1]) + ", its squares about " +
         FormatFixed(100 * p.width_in_frame, 0) +
         " % of the frame's width; all of it in view, in focus, not "
         "overexposed";
}

// Why the board's image to print would be too large (kMaxPhotoPixels, the largest image layerlab writes), or "".
std::string ImageSizeProblem(const PrintedChessboard& board) {
  const size_t pixels = static_cast<size_t>(board.image_width()) * static_cast<size_t>(board.image_height());
  if (pixels <= kMaxPhotoPixels) return "";
  return "the board's image would have " + std::to_string(board.image_width()) + " x " +
         std::to_string(board.image_height()) + " pixels (" + std::to_string(board.pixels_per_square) +
         " to a square), more than " + std::to_string(kMaxPhotoPixels) + "; use fewer squares";
}

std::string Number2(int k) { return (k < 10 ? "0" : "") + std::to_string(k); }

bool PlainFileName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos;
}

PrintedChessboard ReadBoard(Params b) {
  PrintedChessboard board;
  const auto squares = b.integer_pair("squares", 1, 1000);
  if (std::string why = ChessboardSquaresProblem(squares[0], squares[1]); !why.empty()) b.fail("squares", why);
  board.squares_x = static_cast<int>(squares[0]);
  board.squares_y = static_cast<int>(squares[1]);
  board.square_m = b.quantity("square_size", Dimension::kLength);
  if (!(board.square_m > 0)) b.fail("square_size", "the printed square's size must be positive");
  board.image = b.string("image", board.image);
  if (!PlainFileName(board.image))
    b.fail("image", "expected a file name in the plan's folder (no folders, no \"..\"), got \"" + board.image + "\"");
  board.pixels_per_square = static_cast<int>(b.integer("pixels_per_square", 4, 1000, board.pixels_per_square));
  b.check_all_read();
  return board;
}

PlannedBoardPhoto ReadPhotoEntry(Params p) {
  PlannedBoardPhoto photo;
  photo.photo = p.string("photo");
  if (!PlainFileName(photo.photo))
    p.fail("photo", "expected a file name in the plan's folder (no folders, no \"..\"), got \"" + photo.photo + "\"");
  photo.tilt_rad = p.quantity_pair("tilt", Dimension::kAngle, {0, 0});
  for (double t : photo.tilt_rad)
    if (!(std::abs(t) <= kMaxTiltDeg * kRadiansPerDegree))
      p.fail("tilt", "tilts of up to " + FormatFixed(kMaxTiltDeg, 0) + " deg each way; got " + Degrees(t));
  photo.center_in_frame = p.quantity_pair("board_center_in_frame", Dimension::kFraction, {0.5, 0.5});
  for (double c : photo.center_in_frame) p.require_range("board_center_in_frame", c, 0, 1, false, false);
  photo.width_in_frame = p.quantity("board_width_in_frame", Dimension::kFraction, 0.6);
  p.require_range("board_width_in_frame", photo.width_in_frame, 0, 1, true, false);
  photo.advice = p.string("advice", "");
  p.check_all_read();
  return photo;
}

}  // namespace

CameraCapturePlan PlanCameraCaptures(const CameraPlanOptions& options) {
  if (std::string why = ChessboardSquaresProblem(options.squares_x, options.squares_y); !why.empty())
    throw Error("--squares " + std::to_string(options.squares_x) + " " + std::to_string(options.squares_y) + ": " +
                why);
  if (!(options.square_m > 0) || !std::isfinite(options.square_m))
    throw Error("--square-size: the printed square's size must be a positive length");
  if (options.poses < 3 || options.poses > 100)
    throw Error("--poses " + std::to_string(options.poses) +
                ": 3 to 100 photographs (calibrateCamera needs 3 views; 10 to 20 are usual)");
  CameraCapturePlan plan;
  plan.board.squares_x = options.squares_x;
  plan.board.squares_y = options.squares_y;
  plan.board.square_m = options.square_m;
  if (std::string why = ImageSizeProblem(plan.board); !why.empty())
    throw Error("--squares " + std::to_string(options.squares_x) + " " + std::to_string(options.squares_y) + ": " +
                why);
  plan.description = "camera intrinsics from " + std::to_string(options.poses) + " photographs of a printed " +
                     std::to_string(options.squares_x) + " x " + std::to_string(options.squares_y) + " chessboard";
  for (int k = 0; k < options.poses; ++k) {
    const PoseTemplate& t = kPoses[static_cast<size_t>(k) % kPoses.size()];
    // A second round turns the board further (still within 20 to 40 deg) and mirrors the frame's side.
    const int round = k / static_cast<int>(kPoses.size());
    const double more = round % 2 == 0 ? 1.0 : (t.tilt_x_deg == 0 || t.tilt_y_deg == 0 ? 1.15 : 1.4);
    PlannedBoardPhoto p;
    p.photo = "board_" + Number2(k + 1) + "." + options.photo_extension;
    p.tilt_rad = {t.tilt_x_deg * more * kRadiansPerDegree, t.tilt_y_deg * more * kRadiansPerDegree};
    p.center_in_frame = {round % 2 == 0 ? t.center_x : 1 - t.center_x, t.center_y};
    p.width_in_frame = t.width;
    p.advice = Advice(p);
    plan.photos.push_back(p);
  }
  return plan;
}

std::vector<uint8_t> PrintedChessboardImage(const PrintedChessboard& board) {
  if (std::string why = ImageSizeProblem(board); !why.empty()) throw Error(why);
  const int width = board.image_width(), height = board.image_height(), s = board.pixels_per_square;
  std::vector<uint8_t> image(static_cast<size_t>(width) * height, 255);
  for (int r = s; r < height - s; ++r)
    for (int c = s; c < width - s; ++c)
      if (((c / s - 1) + (r / s - 1)) % 2 == 0) image[static_cast<size_t>(r) * width + c] = 0;
  return image;
}

ordered_json CameraCapturePlanToJson(const CameraCapturePlan& plan) {
  ordered_json doc;
  doc["format"] = kCameraCapturesFormat;
  doc["description"] = plan.description;
  doc["response"] = plan.response;
  const PrintedChessboard& b = plan.board;
  doc["board"] = {{"squares", {b.squares_x, b.squares_y}},
                  {"square_size", FormatGeneral(b.square_m * 1e3) + " mm"},
                  {"image", b.image},
                  {"pixels_per_square", b.pixels_per_square}};
  ordered_json photos = ordered_json::array();
  for (const PlannedBoardPhoto& p : plan.photos)
    photos.push_back({{"photo", p.photo},
                      {"tilt", {Degrees(p.tilt_rad[0]), Degrees(p.tilt_rad[1])}},
                      {"board_center_in_frame", {p.center_in_frame[0], p.center_in_frame[1]}},
                      {"board_width_in_frame", p.width_in_frame},
                      {"advice", p.advice}});
  doc["photos"] = photos;
  return doc;
}

CameraCapturePlan ParseCameraCapturePlan(const json& document, const std::string& file) {
  CameraCapturePlan plan;
  Params top(document, {file, ""});
  const std::string format = top.string("format");
  if (format != kCameraCapturesFormat)
    top.fail("format", "unknown camera capture plan format \"" + format + "\"; this layerlab reads \"" +
                           kCameraCapturesFormat + "\"");
  plan.description = top.string("description", "");
  plan.response = top.string("response", "linear");
  if (!ResponseExponent(plan.response))
    top.fail("response", "expected \"linear\" or \"gamma G\" (value^G is linear light, G finite and above 0), got \"" +
                             plan.response + "\"");
  plan.board = ReadBoard(top.object("board"));
  const json& photos = top.raw("photos");
  if (!photos.is_array() || photos.empty())
    top.fail("photos", "expected a non-empty array of photographs, got " + JsonKindName(photos));
  std::set<std::string> names;
  for (size_t i = 0; i < photos.size(); ++i) {
    Params p(photos[i], top.where("photos").child(i));
    plan.photos.push_back(ReadPhotoEntry(p));
    if (!names.insert(plan.photos.back().photo).second)
      p.fail("photo", "\"" + plan.photos.back().photo + "\" is named twice; each photograph needs its own file");
    if (plan.photos.back().photo == plan.board.image)
      p.fail("photo", "\"" + plan.board.image + "\" is the board's image to print, not a photograph");
  }
  top.check_all_read();
  return plan;
}

CameraCapturePlan ReadCameraCapturePlanFile(const std::string& path) {
  return ParseCameraCapturePlan(ReadJsonFile(path), path);
}

}  // namespace layerlab

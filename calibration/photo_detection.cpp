#include "layerlab/calibration/photo_detection.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "layerlab/calibration/board_orientation.h"
#include "layerlab/calibration/detection_noise.h"
#include "layerlab/calibration/photo_files.h"
#include "layerlab/calibration/synthetic_measurements.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/png_header.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

double ResponseGamma(const std::string& response) {
  if (const std::optional<double> g = ResponseExponent(response)) return *g;
  throw Error("unknown response \"" + response + "\": expected \"linear\" or \"gamma G\"");
}

double Quantile(std::vector<float> values, double q) {
  if (values.empty()) return 0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size())));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

// What a photograph without a found board shows where the board should be
// (`area`, from the prediction): its contrast, its noise (from the
// differences of neighboring pixels, robust to the few edges) and its edges'
// width (contrast over the steepest gradients of the image smoothed against
// the noise), against the squares' size.
std::string WhatItShows(const Photo& photo, double square_px, cv::Rect area) {
  area &= cv::Rect(0, 0, photo.width, photo.height);
  if (area.width < 4 || area.height < 4)
    return "the board should lie outside the photograph: is the camera pointed at the panel?";
  cv::Mat image(photo.height, photo.width, CV_32F, const_cast<float*>(photo.pixels.data()));
  cv::Mat roi = image(area).clone(), smooth;
  cv::GaussianBlur(roi, smooth, cv::Size(0, 0), 1.5);
  std::vector<float> differences, gradients;
  for (int r = 0; r + 1 < roi.rows; ++r)
    for (int c = 0; c + 1 < roi.cols; ++c) {
      differences.push_back(std::abs(roi.at<float>(r, c + 1) - roi.at<float>(r, c)));
      gradients.push_back(std::hypot(smooth.at<float>(r, c + 1) - smooth.at<float>(r, c),
                                     smooth.at<float>(r + 1, c) - smooth.at<float>(r, c)));
    }
  const double noise = Quantile(differences, 0.5) / (0.6745 * std::sqrt(2.0));
  // The pattern's contrast at the scale of its squares: the 2 % to 98 % spread of the image averaged over boxes a
  // third of a square wide, less the 4.1 sigma that the averaged noise alone spreads. The squares stay and the
  // noise shrinks by the box's width, so a pattern lost in the noise pixel by pixel is "too noisy", not "no pattern".
  const int box = std::isfinite(square_px) ? std::clamp(static_cast<int>(std::min(square_px, 1e4) / 3), 1, 64) : 1;
  cv::Mat averaged;
  cv::blur(roi, averaged, cv::Size(box, box));
  const std::vector<float> means(averaged.begin<float>(), averaged.end<float>());
  const double averaged_noise = noise / box;
  const double contrast = Quantile(means, 0.98) - Quantile(means, 0.02) - 4.1 * averaged_noise;
  if (!(contrast > 0.02) || !(contrast > 2 * averaged_noise))
    return "the photograph shows no pattern where the board should be (contrast " + FormatFixed(100 * contrast, 1) +
           " % of full scale, noise " + FormatFixed(100 * noise, 2) +
           " %): is the panel showing it, and the camera pointed at it?";
  if (noise > 0.1 * contrast)
    return "the photograph is too noisy (noise " + FormatFixed(100 * noise / contrast, 0) +
           " % of the pattern's contrast): expose longer or lower the gain";
  const double steepest = Quantile(gradients, 0.995);
  const double edge_px = steepest > 0 ? contrast / steepest : INFINITY;
  if (edge_px > 0.25 * square_px)
    return "the photograph is out of focus (edges " + FormatFixed(edge_px, 1) + " px wide against squares of " +
           FormatFixed(square_px, 0) + " px): focus the camera on the panel or stop it down";
  return "the board is not in view whole, or something covers it (contrast " + FormatFixed(100 * contrast, 0) +
         " % of full scale, edges " + FormatFixed(edge_px, 1) + " px wide)";
}

// How many squares across and down the photograph shows in `area` (the board as predicted, widened into its
// white margin): a line across a row of N squares that starts dark crosses N or N + 1 edges, one that starts
// light N or N - 1, and the rows alternate, so the mean over the lines that cross any edge is N. Edges are
// counted with hysteresis about the middle of the area's range, on the image smoothed against the noise.
std::array<int, 2> SquaresSeen(const Photo& photo, cv::Rect area) {
  area &= cv::Rect(0, 0, photo.width, photo.height);
  if (area.width < 8 || area.height < 8) return {0, 0};
  cv::Mat image(photo.height, photo.width, CV_32F, const_cast<float*>(photo.pixels.data()));
  cv::Mat smooth;
  cv::GaussianBlur(image(area), smooth, cv::Size(0, 0), 1.0);
  std::vector<float> values(smooth.begin<float>(), smooth.end<float>());
  const double low = Quantile(values, 0.05), high = Quantile(values, 0.95);
  const double middle = 0.5 * (low + high), band = 0.2 * (high - low);
  if (!(band > 0)) return {0, 0};
  std::array<int, 2> seen = {0, 0};
  for (int axis = 0; axis < 2; ++axis) {  // 0: along rows (squares across), 1: along columns
    const int lines = axis == 0 ? smooth.rows : smooth.cols, length = axis == 0 ? smooth.cols : smooth.rows;
    double edges = 0;
    int crossing = 0;
    for (int line = 0; line < lines; ++line) {
      int count = 0, state = 0;  // 0: not yet known, 1: light, -1: dark
      for (int k = 0; k < length; ++k) {
        const float v = axis == 0 ? smooth.at<float>(line, k) : smooth.at<float>(k, line);
        const int now = v > middle + band ? 1 : v < middle - band ? -1 : state;
        if (state != 0 && now != state) ++count;
        state = now;
      }
      if (count > 0) edges += count, ++crossing;
    }
    if (crossing > 0) seen[axis] = static_cast<int>(std::lround(edges / crossing));
  }
  return seen;
}

// The mean distance from each point to its nearest neighbor: a found board's square size.
double NeighborSpacing(const std::vector<cv::Point2f>& points) {
  double sum = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    double nearest = INFINITY;
    for (size_t j = 0; j < points.size(); ++j)
      if (j != i) nearest = std::min(nearest, static_cast<double>(cv::norm(points[i] - points[j])));
    sum += nearest;
  }
  return sum / static_cast<double>(std::max<size_t>(1, points.size()));
}

std::vector<cv::Point2f> TryBoard(const cv::Mat& image8, int cols, int rows) {
  std::vector<cv::Point2f> corners;
  if (!cv::findChessboardCorners(image8, cv::Size(cols, rows), corners,
                                 cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
    corners.clear();
  return corners;
}

// An 8- or 16-bit PNG (gray, gray and alpha, RGB or RGBA) as fractions of full scale, gray or the mean of RGB.
Photo DecodePng(const std::string& path) {
  Photo photo;
  cv::Mat m;
  try {
    m = cv::imread(path, cv::IMREAD_UNCHANGED);
    if (m.empty()) throw Error(path + ": cannot read it as a PNG (truncated or corrupt)");
    const double full = m.depth() == CV_16U ? 65535.0 : m.depth() == CV_8U ? 255.0 : 0.0;
    if (full == 0) throw Error(path + ": expected an 8- or 16-bit PNG");
    if (m.channels() == 2) {  // gray and alpha: the gray
      cv::Mat gray;
      cv::extractChannel(m, gray, 0);
      m = gray;
    }
    if (m.channels() == 3 || m.channels() == 4)
      cv::cvtColor(m, m, m.channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
    cv::Mat f;
    m.convertTo(f, CV_32F, 1.0 / full);
    photo.width = f.cols, photo.height = f.rows;
    photo.pixels.assign(f.begin<float>(), f.end<float>());
  } catch (const cv::Exception& e) {
    throw Error(path + ": OpenCV cannot decode it: " + e.err);
  }
  return photo;
}

}  // namespace

Photo ReadPhoto(const std::string& path, const std::string& response) {
  const double gamma = ResponseGamma(response);
  Photo photo;
  // By the file's own signature, whatever its name says (a PNG saved as .exr is read as the PNG it is).
  const ImageFileKind kind = ImageFileKindOf(path);
  if (kind == ImageFileKind::kExr) {
    // Y when the file has it, else G: a file with Y is read as Y, so that a bad Y pixel is named as such.
    const std::vector<std::string> present = ReadExrChannelNames(path);
    const bool has_y = std::find(present.begin(), present.end(), "Y") != present.end();
    ExrLimits limits;
    limits.max_pixels = static_cast<long long>(kMaxPhotoPixels);
    Image image = ReadExr(path, {has_y ? "Y" : "G"}, limits);
    photo.width = image.width, photo.height = image.height, photo.pixels = std::move(image.pixels);
  } else if (kind == ImageFileKind::kPng) {
    RequirePngWithinLimit(path, ReadPngHeader(path), kMaxPhotoPixels);
    photo = DecodePng(path);
  } else {
    throw Error(path +
                ": neither an EXR nor a PNG file (by its first bytes): photographs are read from linear EXR or "
                "8/16-bit PNG");
  }
  if (gamma != 1)
    for (float& v : photo.pixels) v = static_cast<float>(std::pow(std::max(v, 0.0f), gamma));
  return photo;
}

std::string OverexposureReason(const Photo& photo, const PhotoCheck& check) {
  size_t clipped = 0;
  for (float v : photo.pixels) clipped += v >= 0.999f;
  const double fraction = static_cast<double>(clipped) / static_cast<double>(std::max<size_t>(1, photo.pixels.size()));
  if (fraction <= check.overexposed_fraction) return "";
  return "overexposed: " + FormatFixed(100 * fraction, 1) +
         " % of the pixels are at full scale; shorten the exposure (or lower the backlight) and photograph it again";
}

namespace {

// The predicted spacing of neighboring corners, in camera pixels.
double PredictedSquarePixels(const std::vector<std::array<double, 2>>& predicted, int cols, int rows) {
  double square_px = 0;
  for (int b = 0; b < rows; ++b)
    for (int a = 0; a + 1 < cols; ++a) {
      const auto& p = predicted[b * cols + a];
      const auto& q = predicted[b * cols + a + 1];
      square_px += std::hypot(q[0] - p[0], q[1] - p[1]) / ((cols - 1) * rows);
    }
  return square_px;
}

// Another plan's board (other square counts) would read below as out of focus or partly covered. Its
// squares are counted over the predicted board widened by half a square and by a whole one (the other
// board may be wider, and beyond its white margin lies the panel's black), and a count that differs from
// the plan's is confirmed by finding its corners. "" when no other board is found.
std::string WrongBoardReason(const Photo& photo, const cv::Mat& image8, const Chessboard& board, double square_px,
                             const cv::Rect& area) {
  std::vector<std::array<int, 2>> tried;
  for (double widen : {0.5, 1.0}) {
    const int margin = std::isfinite(square_px) ? static_cast<int>(std::clamp(widen * square_px, 0.0, 1e4)) : 0;
    const std::array<int, 2> seen = SquaresSeen(
        photo, cv::Rect(area.x - margin, area.y - margin, area.width + 2 * margin, area.height + 2 * margin));
    if ((seen[0] == board.squares_x && seen[1] == board.squares_y) ||
        !ChessboardSquaresProblem(seen[0], seen[1]).empty() ||
        std::find(tried.begin(), tried.end(), seen) != tried.end())
      continue;
    tried.push_back(seen);
    // Squares of the planned size are part of the planned board (too few features, below), not another board.
    if (std::vector<cv::Point2f> other = TryBoard(image8, seen[0] - 1, seen[1] - 1);
        !other.empty() && std::abs(NeighborSpacing(other) / square_px - 1) > 0.05)
      return "wrong chessboard: the photograph shows one of " + std::to_string(seen[0]) + " x " +
             std::to_string(seen[1]) + " squares (its " + std::to_string(seen[0] - 1) + " x " +
             std::to_string(seen[1] - 1) + " inner corners found), the capture plan's has " +
             std::to_string(board.squares_x) + " x " + std::to_string(board.squares_y) +
             ": was it taken with another plan's patterns?";
  }
  return "";
}

// Why the board's corners were not found: another board, too few features, or not found.
std::string BoardNotFoundReason(const Photo& photo, const cv::Mat& image8, const Chessboard& board,
                                const std::vector<std::array<double, 2>>& predicted, double square_px) {
  const int cols = board.corners_x(), rows = board.corners_y();
  double u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
  for (const auto& p : predicted)
    u0 = std::min(u0, p[0]), v0 = std::min(v0, p[1]), u1 = std::max(u1, p[0]), v1 = std::max(v1, p[1]);
  const cv::Rect area(static_cast<int>(u0 - square_px), static_cast<int>(v0 - square_px),
                      static_cast<int>(u1 - u0 + 2 * square_px), static_cast<int>(v1 - v0 + 2 * square_px));
  if (std::string wrong = WrongBoardReason(photo, image8, board, square_px, area); !wrong.empty()) return wrong;
  const std::string shows = WhatItShows(photo, square_px, area);
  // A part of the board found tells "too few features" from "not found".
  for (const auto& [c, r] : std::vector<std::pair<int, int>>{{cols - 2, rows}, {cols, rows - 2}})
    if (c >= 3 && r >= 3 && shows.rfind("the board is not in view", 0) == 0)
      if (std::vector<cv::Point2f> part = TryBoard(image8, c, r); !part.empty())
        return "too few features: " + std::to_string(part.size()) + " of the board's " + std::to_string(cols * rows) +
               " inner corners found (" + shows + ")";
  return "pattern not found: no " + std::to_string(cols) + " x " + std::to_string(rows) + " chessboard corners (" +
         shows + ")";
}

// The board reads the same turned by 180 degrees, and the optics may mirror it: the
// ordering nearest the prediction is the one.
std::vector<int> OrderNearestPrediction(const std::vector<cv::Point2f>& corners,
                                        const std::vector<std::array<double, 2>>& predicted, int cols, int rows) {
  double best = INFINITY;
  std::vector<int> order(predicted.size());  // as found, should no sum be finite
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  for (int flip = 0; flip < 4; ++flip) {
    std::vector<int> candidate(predicted.size());
    double sum = 0;
    for (int b = 0; b < rows; ++b)
      for (int a = 0; a < cols; ++a) {
        const int fa = flip & 1 ? cols - 1 - a : a, fb = flip & 2 ? rows - 1 - b : b;
        const int k = b * cols + a;
        candidate[k] = fb * cols + fa;
        const cv::Point2f& c = corners[candidate[k]];
        sum += std::pow(c.x - predicted[k][0], 2) + std::pow(c.y - predicted[k][1], 2);
      }
    if (sum < best) best = sum, order = candidate;
  }
  return order;
}

}  // namespace

CornerSearch FindChessboardCorners(const Photo& photo, const Chessboard& board,
                                   const std::vector<std::array<double, 2>>& predicted, const PhotoCheck& check) {
  CornerSearch out;
  const int cols = board.corners_x(), rows = board.corners_y();
  if (predicted.size() != static_cast<size_t>(cols * rows))
    throw Error("internal error: " + std::to_string(predicted.size()) + " predicted corners for a " +
                std::to_string(cols) + " x " + std::to_string(rows) + " board");
  if (std::string why = OverexposureReason(photo, check); !why.empty()) {
    out.reason = why;
    return out;
  }
  const double square_px = PredictedSquarePixels(predicted, cols, rows);
  cv::Mat image(photo.height, photo.width, CV_32F, const_cast<float*>(photo.pixels.data()));
  const double white = std::max(1e-6, Quantile(photo.pixels, 0.995));
  cv::Mat image8;
  image.convertTo(image8, CV_8U, 255.0 / white);
  std::vector<cv::Point2f> corners = TryBoard(image8, cols, rows);
  if (corners.empty()) {
    out.reason = BoardNotFoundReason(photo, image8, board, predicted, square_px);
    return out;
  }
  const int window = std::clamp(static_cast<int>(0.4 * square_px), 2, 15);
  cv::cornerSubPix(image, corners, cv::Size(window, window), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  const std::vector<int> order = OrderNearestPrediction(corners, predicted, cols, rows);
  FoundCorners found;
  for (int b = 0; b < rows; ++b)
    for (int a = 0; a < cols; ++a) {
      found.panel_pixels.push_back(board.corner(a, b));
      const cv::Point2f& c = corners[order[b * cols + a]];
      found.camera_pixels.push_back({c.x, c.y});
    }
  if (std::string why = BoardOrientationReason(photo.pixels, photo.width, photo.height, board, found.camera_pixels);
      !why.empty()) {
    out.reason = why;
    return out;
  }
  out.corners = std::move(found);
  return out;
}

namespace {

// Where something with edges lies in the photograph: the bounding box of the pixels whose gradient (of the image
// smoothed against the noise) passes a quarter of the steepest; the whole photograph when none does.
cv::Rect EdgesArea(const Photo& photo) {
  cv::Mat image(photo.height, photo.width, CV_32F, const_cast<float*>(photo.pixels.data()));
  cv::Mat smooth, gx, gy, magnitude;
  cv::GaussianBlur(image, smooth, cv::Size(0, 0), 1.5);
  cv::Sobel(smooth, gx, CV_32F, 1, 0);
  cv::Sobel(smooth, gy, CV_32F, 0, 1);
  cv::magnitude(gx, gy, magnitude);
  double steepest = 0;
  cv::minMaxLoc(magnitude, nullptr, &steepest);
  const cv::Rect box = steepest > 0 ? cv::boundingRect(magnitude > 0.25 * steepest) : cv::Rect();
  return box.area() > 0 ? box : cv::Rect(0, 0, photo.width, photo.height);
}

// Why a printed board was not found: another board (the largest chessboard in view, found by OpenCV's
// sector-based finder allowed any size above 3 x 3 inner corners), else what the photograph shows.
std::string PrintedBoardNotFoundReason(const Photo& photo, const cv::Mat& image8, int squares_x, int squares_y) {
  std::vector<cv::Point2f> corners;
  cv::Mat meta;
  if (cv::findChessboardCornersSB(image8, cv::Size(3, 3), corners, cv::CALIB_CB_LARGER, meta) && !meta.empty()) {
    // Named the way the plan names its own: the longer side first if the plan's is.
    int sx = meta.cols + 1, sy = meta.rows + 1;
    if ((sx > sy) != (squares_x > squares_y)) std::swap(sx, sy);
    if (!(sx == squares_x && sy == squares_y) && !(sx == squares_y && sy == squares_x))
      return "wrong chessboard: the photograph shows one of " + std::to_string(sx) + " x " + std::to_string(sy) +
             " squares (its " + std::to_string(sx - 1) + " x " + std::to_string(sy - 1) +
             " inner corners found), the plan's has " + std::to_string(squares_x) + " x " + std::to_string(squares_y) +
             ": another board, or part of this one out of view?";
  }
  const cv::Rect area = EdgesArea(photo);
  const double square_px = std::min(area.width / (squares_x + 2.0), area.height / (squares_y + 2.0));
  return "pattern not found: no " + std::to_string(squares_x - 1) + " x " + std::to_string(squares_y - 1) +
         " chessboard corners (" + WhatItShows(photo, square_px, area) + ")";
}

}  // namespace

BoardCorners FindPrintedChessboard(const Photo& photo, int squares_x, int squares_y, const PhotoCheck& check) {
  if (std::string why = ChessboardSquaresProblem(squares_x, squares_y); !why.empty()) throw Error(why);
  BoardCorners out;
  if (std::string why = OverexposureReason(photo, check); !why.empty()) {
    out.reason = why;
    return out;
  }
  cv::Mat image(photo.height, photo.width, CV_32F, const_cast<float*>(photo.pixels.data()));
  const double white = std::max(1e-6, Quantile(photo.pixels, 0.995));
  cv::Mat image8;
  image.convertTo(image8, CV_8U, 255.0 / white);
  std::vector<cv::Point2f> corners = TryBoard(image8, squares_x - 1, squares_y - 1);
  if (corners.empty()) {
    out.reason = PrintedBoardNotFoundReason(photo, image8, squares_x, squares_y);
    return out;
  }
  const int window = std::clamp(static_cast<int>(0.4 * NeighborSpacing(corners)), 2, 15);
  cv::cornerSubPix(image, corners, cv::Size(window, window), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-4));
  for (const cv::Point2f& c : corners) out.camera_pixels.push_back({c.x, c.y});
  return out;
}

namespace {

// The photographs of a capture plan, one by one: a chessboard's corners
// become markers, a luminance step's photograph the mean of the panel's middle.
class CaptureDetector {
 public:
  CaptureDetector(const std::string& folder, const CapturePlan& plan, const DisplaySystem& designed,
                  const CameraIntrinsics& camera, const PhotoCheck& check, PhotoFormat format)
      : folder_(folder), plan_(plan), designed_(designed), camera_(camera), check_(check), format_(format) {
    d_.measurements.file = (std::filesystem::path(folder) / "captures.json").string();
    d_.measurements.description = "detected from the photographs in " + folder;
    d_.measurements.camera = camera;
  }

  Detection Detect() {
    for (const PlannedCapture& c : plan_.captures) {
      const PhotoFile file = LocatePhoto(folder_, c.photo, format_);
      const std::string& path = file.path;
      // A failure names the file read, and the plan's name when it is another.
      const std::string named =
          file.other_name ? std::filesystem::path(path).filename().string() + " (for " + c.photo + ")" : c.photo;
      const VirtualLayer& layer = LayerNamed(c.panel);
      // One unusable photograph is named and the others go on, whatever OpenCV makes of it.
      try {
        files_.Read(c.photo, file);
        const Photo photo = ReadPhoto(path, plan_.response);
        const std::optional<std::string> failure = c.kind == CaptureKind::kChessboard
                                                       ? DetectChessboard(c, path, photo, layer)
                                                       : DetectLuminance(c, path, photo, layer);
        if (failure) d_.failures.push_back({named, *failure});
      } catch (const Error& e) {
        d_.failures.push_back({named, e.what()});
      } catch (const cv::Exception& e) {
        d_.failures.push_back({named, path + ": OpenCV failed on it: " + e.err});
      }
    }
    for (const VirtualLayer& layer : designed_.layers)
      if (auto it = luminance_.find(layer.name); it != luminance_.end())
        d_.measurements.luminance.push_back(it->second);
    d_.notes = files_.Notes(format_, plan_.response);
    // Once per board that a chessboard photograph is taken of.
    for (const Chessboard& board : plan_.chessboards)
      if (std::any_of(plan_.captures.begin(), plan_.captures.end(), [&](const PlannedCapture& c) {
            return c.kind == CaptureKind::kChessboard && c.panel == board.panel;
          }))
        if (std::string note = UncheckedOrientationNote(board); !note.empty()) d_.warnings.push_back(note);
    return std::move(d_);
  }

 private:
  const VirtualLayer& LayerNamed(const std::string& panel) const {
    for (const VirtualLayer& layer : designed_.layers)
      if (layer.name == panel) return layer;
    throw Error(designed_.file + ": the capture plan names panel \"" + panel + "\", which the scene does not have");
  }

  // The capture at `position` that has no markers of `panel` yet, or a new one there: a capture holds each
  // panel once (docs/measurements-format.md), so every photograph of a repeated capture is kept as one more.
  Capture& CaptureFor(const std::array<double, 2>& position, const std::string& panel, const std::string& path) {
    for (Capture& capture : d_.measurements.captures)
      if (capture.camera_position == position && std::none_of(capture.panels.begin(), capture.panels.end(),
                                                              [&](const PanelMarkers& p) { return p.panel == panel; }))
        return capture;
    Capture capture;
    capture.camera_position = position;
    capture.where = {path, ""};
    d_.measurements.captures.push_back(capture);
    return d_.measurements.captures.back();
  }

  // The photograph's chessboard corners as markers of its capture; the failure, if any.
  std::optional<std::string> DetectChessboard(const PlannedCapture& c, const std::string& path, const Photo& photo,
                                              const VirtualLayer& layer) {
    const Chessboard& board = *plan_.chessboard(c.panel);
    std::vector<std::array<double, 2>> predicted;
    for (int b = 0; b < board.corners_y(); ++b)
      for (int a = 0; a < board.corners_x(); ++a) {
        const auto pixel = board.corner(a, b);
        auto angle = ImagedMarker(designed_, layer, pixel[0], pixel[1], {}, c.camera_position);
        if (!std::isfinite(angle[0]) || !std::isfinite(angle[1])) {
          // The scene's real lens loses the ray to this corner: its first-order place, good enough to order
          // the corners found and to size the search.
          VirtualLayer first_order = layer;
          first_order.ray_map.reset();
          angle = ImagedMarker(designed_, first_order, pixel[0], pixel[1], {}, c.camera_position);
        }
        predicted.push_back(CameraPixelFromAngle(camera_, angle[0], angle[1]));
      }
    CornerSearch search = FindChessboardCorners(photo, board, predicted, check_);
    if (!search.corners) return search.reason;
    Capture& capture = CaptureFor(c.camera_position, c.panel, path);
    PanelMarkers markers;
    markers.panel = c.panel;
    markers.where = {path, ""};
    for (size_t k = 0; k < search.corners->panel_pixels.size(); ++k) {
      MarkerObservation m;
      m.col = search.corners->panel_pixels[k][0];
      m.row = search.corners->panel_pixels[k][1];
      const auto& uv = search.corners->camera_pixels[k];
      const auto angle = AngleFromCameraPixel(camera_, uv[0], uv[1]);
      if (!angle) continue;  // beyond the radius where the distortion folds back
      m.angle_x = (*angle)[0];
      m.angle_y = (*angle)[1];
      m.camera_pixel = uv;
      m.where = {path, ""};
      markers.markers.push_back(m);
    }
    markers.detection_noise = EstimateBoardNoise(markers.markers);
    d_.corners += markers.markers.size();
    capture.panels.push_back(std::move(markers));
    return std::nullopt;
  }

  // The photograph's mean over the middle of the panel as a step of its luminance curve; the failure, if any.
  std::optional<std::string> DetectLuminance(const PlannedCapture& c, const std::string& path, const Photo& photo,
                                             const VirtualLayer& layer) {
    if (std::string why = OverexposureReason(photo, check_); !why.empty()) return why;
    // The mean over the camera pixels that see the middle half of the active region (by the design).
    const PanelSpec& p = layer.panel;
    double sum = 0;
    size_t n = 0;
    for (int v = 0; v < photo.height; ++v)
      for (int u = 0; u < photo.width; ++u) {
        const auto angle = AngleFromCameraPixel(camera_, u, v);
        if (!angle) continue;
        const auto pixel = PanelPixelAt(
            layer, PanelPointOfRay(layer, c.camera_position, {std::tan((*angle)[0]), std::tan((*angle)[1])}));
        const double x = (pixel[0] - static_cast<double>(p.active_left)) / static_cast<double>(p.active_cols);
        const double y = (pixel[1] - static_cast<double>(p.active_top)) / static_cast<double>(p.active_rows);
        if (x > 0.25 && x < 0.75 && y > 0.25 && y < 0.75) {
          sum += photo.pixels[static_cast<size_t>(v) * photo.width + u];
          ++n;
        }
      }
    if (n < 16)
      return "the middle of the panel is not in the photograph (" + std::to_string(n) +
             " pixels see it): point the camera at the panel";
    PanelLuminance& curve = luminance_[c.panel];
    curve.panel = c.panel;
    curve.levels = InputLevels::k8Bit;
    curve.where = {path, ""};
    curve.samples.push_back({c.level / 255.0, sum / static_cast<double>(n) / c.exposure, {path, ""}});
    ++d_.luminance_steps;
    return std::nullopt;
  }

  const std::string& folder_;
  const CapturePlan& plan_;
  const DisplaySystem& designed_;
  const CameraIntrinsics& camera_;
  const PhotoCheck& check_;
  const PhotoFormat format_;
  PhotoFilesRead files_;
  Detection d_;
  std::map<std::string, PanelLuminance> luminance_;
};

}  // namespace

Detection DetectCaptures(const std::string& folder, const CapturePlan& plan, const DisplaySystem& designed,
                         const std::optional<CameraIntrinsics>& camera_option, const PhotoCheck& check,
                         PhotoFormat format) {
  const std::optional<CameraIntrinsics> camera = camera_option ? camera_option : plan.camera;
  if (!camera)
    throw Error("the camera's intrinsics are needed: give them in the capture plan's \"camera\" or with --camera FILE");
  return CaptureDetector(folder, plan, designed, *camera, check, format).Detect();
}

}  // namespace layerlab

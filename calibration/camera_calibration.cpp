#include "layerlab/calibration/camera_calibration.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/version.hpp>

#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

// OpenCV before 4.7 divides the residuals' sum of squares by the number of corners less the parameters,
// where the residuals are two per corner (opencv/opencv#22992): its variances come out about twice too large.
double OpenCVVarianceScale(size_t corners, size_t parameters) {
#if CV_VERSION_MAJOR < 4 || (CV_VERSION_MAJOR == 4 && CV_VERSION_MINOR < 7)
  const double n = static_cast<double>(corners), p = static_cast<double>(parameters);
  return (n - p) / (2 * n - p);
#else
  (void)corners, (void)parameters;
  return 1.0;
#endif
}

std::string FailureList(const std::vector<PhotoFailure>& failures) {
  std::string out;
  for (const PhotoFailure& f : failures) out += "\n  " + f.photo + ": " + f.reason;
  return out;
}

// The estimate's uncertainty from OpenCV's standard deviations (fx, fy, cx, cy, k1, k2, p1, p2, k3, ...).
CameraIntrinsicsUncertainty Uncertainty(const cv::Mat& std_devs, size_t corners, size_t views, double rms) {
  const double scale = std::sqrt(OpenCVVarianceScale(corners, 6 + 6 * views));
  CameraIntrinsicsUncertainty u;
  u.fx_px = scale * std_devs.at<double>(0);
  u.fy_px = scale * std_devs.at<double>(1);
  u.cx_px = scale * std_devs.at<double>(2);
  u.cy_px = scale * std_devs.at<double>(3);
  u.k1 = scale * std_devs.at<double>(4);
  u.k2 = scale * std_devs.at<double>(5);
  u.rms_reprojection_px = rms;
  return u;
}

// Refuses an estimate whose focal length the poses do not determine, or that is not finite.
void RefuseUndetermined(const IntrinsicsEstimate& e) {
  const CameraIntrinsics& c = e.camera;
  const CameraIntrinsicsUncertainty& u = *c.uncertainty;
  double tilt = 0;
  for (const BoardView& v : e.views) tilt = std::max(tilt, v.tilt_rad);
  const std::string advice =
      " (the board's largest tilt from face-on seen in them: " + FormatFixed(tilt * kDegreesPerRadian, 1) +
      " deg); photograph it turned by 20 to 40 deg about both axes, as the plan's "
      "\"advice\" says, and near the corners of the frame";
  for (double v : {c.fx, c.fy, c.cx, c.cy, c.k1, c.k2, u.fx_px, u.fy_px, u.cx_px, u.cy_px, u.k1, u.k2})
    if (!std::isfinite(v))
      throw Error("the calibration of the camera did not converge to finite intrinsics from " +
                  std::to_string(e.views.size()) + " photographs" + advice);
  const double relative = std::max(u.fx_px / c.fx, u.fy_px / c.fy);
  if (!(c.fx > 0) || !(c.fy > 0) || !(relative <= kMaxFocalLengthRelativeStd))
    throw Error("the photographs do not determine the focal length: fx = " + FormatGeneral(c.fx) + " +- " +
                FormatGeneral(u.fx_px) + " px, fy = " + FormatGeneral(c.fy) + " +- " + FormatGeneral(u.fy_px) +
                " px (one standard deviation; at most " + FormatFixed(100 * kMaxFocalLengthRelativeStd, 0) +
                " % is accepted)" + advice);
}

}  // namespace

IntrinsicsEstimate CalibrateFromViews(const PrintedChessboard& board, std::vector<BoardView> views, int width,
                                      int height) {
  IntrinsicsEstimate e;
  e.width = width;
  e.height = height;
  if (views.size() < kMinIntrinsicsViews)
    throw Error("the intrinsics need the board in at least " + std::to_string(kMinIntrinsicsViews) + " photographs; " +
                std::to_string(views.size()) + " show it");
  std::vector<cv::Point3f> grid;
  for (int b = 0; b < board.corners_y(); ++b)
    for (int a = 0; a < board.corners_x(); ++a)
      grid.emplace_back(static_cast<float>((a + 1) * board.square_m), static_cast<float>((b + 1) * board.square_m),
                        0.0f);
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  size_t corners = 0;
  for (const BoardView& v : views) {
    if (v.corners.size() != grid.size())
      throw Error(v.photo + ": internal error: " + std::to_string(v.corners.size()) + " corners for a board of " +
                  std::to_string(grid.size()));
    object_points.push_back(grid);
    image_points.emplace_back();
    for (const auto& c : v.corners)
      image_points.back().emplace_back(static_cast<float>(c[0]), static_cast<float>(c[1]));
    corners += v.corners.size();
  }
  cv::Mat camera_matrix = cv::Mat::eye(3, 3, CV_64F), distortion = cv::Mat::zeros(5, 1, CV_64F);
  cv::Mat std_intrinsics, std_extrinsics, per_view;
  std::vector<cv::Mat> rvecs, tvecs;
  // camera_model.h's model: radial k1, k2 only (no tangential p1, p2, no k3; k4-k6 stay off without
  // CALIB_RATIONAL_MODEL), fx and fy free, no skew.
  const int flags = cv::CALIB_ZERO_TANGENT_DIST | cv::CALIB_FIX_K3;
  const double rms = cv::calibrateCamera(object_points, image_points, cv::Size(width, height), camera_matrix,
                                         distortion, rvecs, tvecs, std_intrinsics, std_extrinsics, per_view, flags,
                                         cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12));
  e.camera.fx = camera_matrix.at<double>(0, 0);
  e.camera.fy = camera_matrix.at<double>(1, 1);
  e.camera.cx = camera_matrix.at<double>(0, 2);
  e.camera.cy = camera_matrix.at<double>(1, 2);
  e.camera.k1 = distortion.at<double>(0);
  e.camera.k2 = distortion.at<double>(1);
  e.camera.uncertainty = Uncertainty(std_intrinsics, corners, views.size(), rms);
  for (size_t i = 0; i < views.size(); ++i) {
    views[i].rms_px = per_view.at<double>(static_cast<int>(i));
    cv::Mat rotation;
    cv::Rodrigues(rvecs[i], rotation);
    views[i].tilt_rad = std::acos(std::min(1.0, std::abs(rotation.at<double>(2, 2))));
  }
  e.views = std::move(views);
  RefuseUndetermined(e);
  return e;
}

IntrinsicsEstimate EstimateIntrinsics(const std::string& folder, const CameraCapturePlan& plan,
                                      const PhotoCheck& check) {
  std::vector<BoardView> views;
  std::vector<PhotoFailure> failures;
  int width = 0, height = 0;
  for (const PlannedBoardPhoto& planned : plan.photos) {
    const std::string path = (std::filesystem::path(folder) / planned.photo).string();
    // One unusable photograph is named and the others go on, whatever OpenCV makes of it.
    try {
      const Photo photo = ReadPhoto(path, plan.response);
      if (!views.empty() && (photo.width != width || photo.height != height)) {
        failures.push_back({planned.photo, "its size, " + std::to_string(photo.width) + " x " +
                                               std::to_string(photo.height) + " pixels, differs from " +
                                               views.front().photo + "'s " + std::to_string(width) + " x " +
                                               std::to_string(height) +
                                               ": intrinsics belong to one image size (no cropping or scaling)"});
        continue;
      }
      BoardCorners found = FindPrintedChessboard(photo, plan.board.squares_x, plan.board.squares_y, check);
      if (found.camera_pixels.empty()) {
        failures.push_back({planned.photo, found.reason});
        continue;
      }
      width = photo.width, height = photo.height;
      views.push_back({planned.photo, std::move(found.camera_pixels), 0, 0});
    } catch (const Error& e) {
      failures.push_back({planned.photo, e.what()});
    } catch (const cv::Exception& e) {
      failures.push_back({planned.photo, path + ": OpenCV failed on it: " + e.err});
    }
  }
  if (views.size() < kMinIntrinsicsViews)
    throw Error(folder + ": the intrinsics need the board in at least " + std::to_string(kMinIntrinsicsViews) +
                " photographs; " + std::to_string(views.size()) + " of " + std::to_string(plan.photos.size()) +
                " show it, the others cannot be used:" + FailureList(failures));
  IntrinsicsEstimate e;
  try {
    e = CalibrateFromViews(plan.board, std::move(views), width, height);
  } catch (const cv::Exception& x) {
    throw Error(folder + ": OpenCV's calibrateCamera failed: " + x.err);
  } catch (const Error& x) {
    throw Error(folder + ": " + x.what());
  }
  e.failures = std::move(failures);
  return e;
}

}  // namespace layerlab

// The camera's intrinsics from photographs of a printed chessboard (issue 43):
// the plan (camera_capture_plan.h), the synthetic photographs
// (synthetic_chessboard.h), the estimate with its standard deviations
// (camera_calibration.h) and the camera file's uncertainty fields.

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>

#include "layerlab/calibration/camera_calibration.h"
#include "layerlab/calibration/camera_capture_plan.h"
#include "layerlab/calibration/measurements.h"
#include "layerlab/calibration/synthetic_chessboard.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/units.h"
#include "layerlab/tests/photo_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::ErrorOf;
using testing::FreshFolder;

// The true camera: fx and fy differ, the principal point off the middle, barrel distortion.
PhotoCamera TrueCamera() {
  PhotoCamera c;
  c.intrinsics = {360, 365, 203.3, 146.8, -0.05, 0.02, std::nullopt};
  c.width = 400;
  c.height = 300;
  c.white = 0.7;
  c.full_well = 20000;
  c.read_noise = 0.002;
  c.supersampling = 2;
  c.psf_sigma_px = 0.8;
  return c;
}

// Renders every photograph of `plan` into `folder` (linear EXR); `board` is the board photographed.
void Photograph(const std::string& folder, CameraCapturePlan& plan, const PrintedChessboard& board) {
  const PhotoCamera camera = TrueCamera();
  const BoardPhotoRenderer renderer(camera);
  for (size_t k = 0; k < plan.photos.size(); ++k) {
    PlannedBoardPhoto& p = plan.photos[k];
    p.photo = "board_" + std::to_string(k) + ".exr";
    WriteExr(folder + "/" + p.photo, renderer.Render(board, PoseOfPlannedPhoto(p, plan.board, camera), k),
             ExrCompression::kNone);
  }
}

// Ten planned poses and, last, a photograph of another board (8 x 5 squares) at the first pose.
struct Session {
  std::string folder;
  CameraCapturePlan plan;
  IntrinsicsEstimate estimate;
};

const Session& TenPoses() {
  static const Session session = [] {
    Session s;
    s.folder = FreshFolder("camera_intrinsics");
    CameraPlanOptions options;
    options.poses = 10;
    s.plan = PlanCameraCaptures(options);
    Photograph(s.folder, s.plan, s.plan.board);
    PlannedBoardPhoto wrong = s.plan.photos.front();
    wrong.photo = "wrong_board.exr";
    PrintedChessboard other = s.plan.board;
    other.squares_x = 8;
    other.squares_y = 5;
    const PhotoCamera camera = TrueCamera();
    WriteExr(s.folder + "/" + wrong.photo,
             BoardPhotoRenderer(camera).Render(other, PoseOfPlannedPhoto(wrong, other, camera), 99),
             ExrCompression::kNone);
    s.plan.photos.push_back(wrong);
    s.estimate = EstimateIntrinsics(s.folder, s.plan);
    return s;
  }();
  return session;
}

// ... and the photograph of another board is named with its square counts while the others go on.
TEST(CameraIntrinsicsTest, EveryIntrinsicWithinThreeSigmaOfTheTruth) {
  const IntrinsicsEstimate& e = TenPoses().estimate;
  ASSERT_EQ(e.failures.size(), 1u);
  EXPECT_EQ(e.failures[0].photo, "wrong_board.exr");
  EXPECT_NE(e.failures[0].reason.find("wrong chessboard: the photograph shows one of 8 x 5 squares"), std::string::npos)
      << e.failures[0].reason;
  const CameraIntrinsics truth = TrueCamera().intrinsics;
  ASSERT_TRUE(e.camera.uncertainty);
  const CameraIntrinsicsUncertainty& u = *e.camera.uncertainty;
  EXPECT_EQ(e.views.size(), 10u);
  const std::array<std::tuple<const char*, double, double, double>, 6> rows = {{{"fx", e.camera.fx, truth.fx, u.fx_px},
                                                                                {"fy", e.camera.fy, truth.fy, u.fy_px},
                                                                                {"cx", e.camera.cx, truth.cx, u.cx_px},
                                                                                {"cy", e.camera.cy, truth.cy, u.cy_px},
                                                                                {"k1", e.camera.k1, truth.k1, u.k1},
                                                                                {"k2", e.camera.k2, truth.k2, u.k2}}};
  for (const auto& [name, estimated, true_value, sigma] : rows) {
    EXPECT_GT(sigma, 0) << name;
    EXPECT_LE(std::abs(estimated - true_value), 3 * sigma)
        << name << ": " << estimated << " +- " << sigma << ", truth " << true_value;
  }
  // Plausible, not merely large enough to cover the error: the focal lengths to 1 %, the principal point to
  // 1 % of the width, the distortion to a fifth of k1.
  EXPECT_LT(u.fx_px, 0.01 * truth.fx);
  EXPECT_LT(u.fy_px, 0.01 * truth.fy);
  EXPECT_LT(u.cx_px, 0.01 * TrueCamera().width);
  EXPECT_LT(u.cy_px, 0.01 * TrueCamera().width);
  EXPECT_LT(u.k1, 0.2 * std::abs(truth.k1));
  EXPECT_GT(u.rms_reprojection_px, 0.0);
  EXPECT_LT(u.rms_reprojection_px, 0.2);
}

// The standard deviations against the least-squares covariance computed here on its own: each view's pose
// fitted to the estimated intrinsics (cv::solvePnP), the Jacobian of every corner's residual by central
// differences of a projection written out below, sigma^2 = residual sum of squares / (2 corners - parameters),
// covariance sigma^2 (J^T J)^-1. OpenCV before 4.7 divides by (corners - parameters) instead.
TEST(CameraIntrinsicsTest, TheStandardDeviationsAreTheLeastSquaresCovariancesOnes) {
  const Session& s = TenPoses();
  const IntrinsicsEstimate& e = s.estimate;
  const PrintedChessboard& board = s.plan.board;
  std::vector<cv::Point3d> grid;
  for (int b = 0; b < board.corners_y(); ++b)
    for (int a = 0; a < board.corners_x(); ++a)
      grid.emplace_back((a + 1) * board.square_m, (b + 1) * board.square_m, 0);
  const size_t views = e.views.size(), corners = grid.size() * views, parameters = 6 + 6 * views;
  Eigen::VectorXd p(static_cast<Eigen::Index>(parameters));
  p.head<6>() << e.camera.fx, e.camera.fy, e.camera.cx, e.camera.cy, e.camera.k1, e.camera.k2;
  const cv::Matx33d matrix(e.camera.fx, 0, e.camera.cx, 0, e.camera.fy, e.camera.cy, 0, 0, 1);
  const std::vector<double> distortion = {e.camera.k1, e.camera.k2, 0, 0, 0};
  for (size_t i = 0; i < views; ++i) {
    std::vector<cv::Point2d> seen;
    for (const auto& c : e.views[i].corners) seen.emplace_back(c[0], c[1]);
    cv::Vec3d rotation, translation;
    ASSERT_TRUE(cv::solvePnP(grid, seen, matrix, distortion, rotation, translation));
    for (int k = 0; k < 3; ++k) {
      p[static_cast<Eigen::Index>(6 + 6 * i + k)] = rotation[k];
      p[static_cast<Eigen::Index>(9 + 6 * i + k)] = translation[k];
    }
  }
  auto residuals = [&](const Eigen::VectorXd& q) {
    Eigen::VectorXd r(static_cast<Eigen::Index>(2 * corners));
    Eigen::Index n = 0;
    for (size_t i = 0; i < views; ++i) {
      const Eigen::Vector3d w = q.segment<3>(static_cast<Eigen::Index>(6 + 6 * i));
      const Eigen::Matrix3d rotation =
          w.norm() > 0 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
      for (size_t j = 0; j < grid.size(); ++j) {
        const Eigen::Vector3d c =
            rotation * Eigen::Vector3d(grid[j].x, grid[j].y, 0) + q.segment<3>(static_cast<Eigen::Index>(9 + 6 * i));
        const double x = c[0] / c[2], y = c[1] / c[2], r2 = x * x + y * y, g = 1 + q[4] * r2 + q[5] * r2 * r2;
        r[n++] = q[0] * g * x + q[2] - e.views[i].corners[j][0];
        r[n++] = q[1] * g * y + q[3] - e.views[i].corners[j][1];
      }
    }
    return r;
  };
  Eigen::MatrixXd jacobian(static_cast<Eigen::Index>(2 * corners), static_cast<Eigen::Index>(parameters));
  for (Eigen::Index k = 0; k < jacobian.cols(); ++k) {
    const double h = 1e-6 * std::max(1.0, std::abs(p[k]));
    Eigen::VectorXd plus = p, minus = p;
    plus[k] += h;
    minus[k] -= h;
    jacobian.col(k) = (residuals(plus) - residuals(minus)) / (2 * h);
  }
  const double sigma2 = residuals(p).squaredNorm() / static_cast<double>(2 * corners - parameters);
  const Eigen::MatrixXd covariance = sigma2 * (jacobian.transpose() * jacobian).inverse();
  const CameraIntrinsicsUncertainty& u = *e.camera.uncertainty;
  const std::array<double, 6> reported = {u.fx_px, u.fy_px, u.cx_px, u.cy_px, u.k1, u.k2};
  for (Eigen::Index k = 0; k < 6; ++k)
    EXPECT_TRUE(testing::Close(reported[static_cast<size_t>(k)], std::sqrt(covariance(k, k)), 0.03))
        << "intrinsic " << k << ": reported " << reported[static_cast<size_t>(k)] << ", covariance's "
        << std::sqrt(covariance(k, k));
  // The RMS reprojection error is over the corners (OpenCV's convention), sqrt(sum of squares / corners).
  EXPECT_TRUE(testing::Close(u.rms_reprojection_px,
                             std::sqrt(residuals(p).squaredNorm() / static_cast<double>(corners)), 0.01));
}

// The renderer against camera_model.h: every corner found in a photograph lies where the true camera projects
// the board's corner (camera coordinates (x, y, z), y down: visual angles atan(x / z), atan(-y / z)), to the
// corner finder's accuracy. A renderer half a pixel off (pixel centers) or with another distortion fails here.
TEST(CameraIntrinsicsTest, TheCornersFoundLieWhereTheTrueCameraProjectsThem) {
  const Session& s = TenPoses();
  const PhotoCamera camera = TrueCamera();
  for (size_t i = 0; i < 3; ++i) {
    const BoardView& view = s.estimate.views[i];
    ASSERT_EQ(view.photo, s.plan.photos[i].photo);
    const BoardPose pose = PoseOfPlannedPhoto(s.plan.photos[i], s.plan.board, camera);
    std::vector<std::array<double, 2>> projected;
    for (int b = 0; b < s.plan.board.corners_y(); ++b)
      for (int a = 0; a < s.plan.board.corners_x(); ++a) {
        const auto c = BoardCorner(s.plan.board, pose, a, b);
        projected.push_back(CameraPixelFromAngle(camera.intrinsics, std::atan(c[0] / c[2]), std::atan(-c[1] / c[2])));
      }
    // The corners come row by row from either end (the grid reads the same turned by 180 degrees): the
    // nearer ordering's mean offset (a shift of the whole image) and RMS distance.
    const size_t n = projected.size();
    double best_rms = INFINITY, best_shift = INFINITY;
    for (bool reversed : {false, true}) {
      double du = 0, dv = 0, squares = 0;
      for (size_t k = 0; k < n; ++k) {
        const auto& q = projected[reversed ? n - 1 - k : k];
        du += view.corners[k][0] - q[0];
        dv += view.corners[k][1] - q[1];
        squares += std::pow(view.corners[k][0] - q[0], 2) + std::pow(view.corners[k][1] - q[1], 2);
      }
      if (std::sqrt(squares / n) < best_rms) best_rms = std::sqrt(squares / n), best_shift = std::hypot(du, dv) / n;
    }
    EXPECT_LT(best_rms, 0.15) << view.photo << ": RMS distance, px";
    EXPECT_LT(best_shift, 0.06) << view.photo << ": mean offset, px";
  }
}

}  // namespace
}  // namespace layerlab

namespace layerlab {
namespace {

// The projection of one point worked by hand: camera coordinates (0.1, -0.05, 0.5) m (x right, y down), so
// x = 0.2, y = -0.1, r^2 = 0.05, 1 + k1 r^2 + k2 r^4 = 1 - 0.0025 + 0.000025 = 0.997525, and
// u = 320.3 + 400 * 0.2 * 0.997525 = 400.102, v = 240.7 + 410 * -0.1 * 0.997525 = 199.801475.
TEST(CameraIntrinsicsTest, LayerlabsModelAndOpenCVsProjectAPointAsWorkedByHand) {
  const CameraIntrinsics k{400, 410, 320.3, 240.7, -0.05, 0.01, std::nullopt};
  const double u = 400.102, v = 199.801475;
  // camera_model.h speaks in visual angles, y up: the point's are atan(0.2) and atan(0.1).
  const auto pixel = CameraPixelFromAngle(k, std::atan(0.2), std::atan(0.1));
  EXPECT_NEAR(pixel[0], u, 1e-9);
  EXPECT_NEAR(pixel[1], v, 1e-9);
  const auto angle = AngleFromCameraPixel(k, u, v);
  ASSERT_TRUE(angle);
  EXPECT_NEAR((*angle)[0], std::atan(0.2), 1e-12);
  EXPECT_NEAR((*angle)[1], std::atan(0.1), 1e-12);
  // OpenCV with the coefficients camera_calibration.cpp estimates (k1, k2; p1 = p2 = k3 = 0).
  const cv::Matx33d matrix(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const std::vector<double> distortion = {k.k1, k.k2, 0, 0, 0};
  std::vector<cv::Point2d> projected;
  cv::projectPoints(std::vector<cv::Point3d>{{0.1, -0.05, 0.5}}, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), matrix,
                    distortion, projected);
  EXPECT_NEAR(projected[0].x, u, 1e-9);
  EXPECT_NEAR(projected[0].y, v, 1e-9);
}

// A board seen nearly face-on in every photograph (tilts of 2 deg at most) gives focal length over distance only.
TEST(CameraIntrinsicsTest, FaceOnPhotographsAreRefusedForTheFocalLength) {
  const std::string folder = FreshFolder("camera_intrinsics_face_on");
  CameraPlanOptions options;
  options.poses = 5;
  CameraCapturePlan plan = PlanCameraCaptures(options);
  const std::array<std::array<double, 2>, 5> tilts_deg = {{{1, 0}, {0, -1.5}, {2, 1}, {-1, -2}, {0.5, 1.5}}};
  for (size_t k = 0; k < plan.photos.size(); ++k) {
    plan.photos[k].tilt_rad = {tilts_deg[k][0] * kRadiansPerDegree, tilts_deg[k][1] * kRadiansPerDegree};
    plan.photos[k].center_in_frame = {0.4 + 0.05 * k, 0.6 - 0.05 * k};
    plan.photos[k].width_in_frame = 0.5 + 0.05 * k;
  }
  Photograph(folder, plan, plan.board);
  const std::string error = ErrorOf([&] { EstimateIntrinsics(folder, plan); });
  EXPECT_NE(error.find("the photographs do not determine the focal length"), std::string::npos) << error;
  EXPECT_NE(error.find("turned by 20 to 40 deg about both axes"), std::string::npos) << error;
}

TEST(CameraIntrinsicsTest, FewerThanThreeUsablePhotographsAreRefusedNamingTheOthers) {
  const std::string folder = FreshFolder("camera_intrinsics_few");
  CameraPlanOptions options;
  options.poses = 3;
  CameraCapturePlan plan = PlanCameraCaptures(options);
  plan.photos.resize(2);
  Photograph(folder, plan, plan.board);
  plan.photos.push_back(plan.photos.front());
  plan.photos.back().photo = "missing.exr";
  plan.photos.push_back(plan.photos.front());
  plan.photos.back().photo = "notes.txt";
  { std::ofstream(folder + "/notes.txt") << "not a photograph\n"; }
  const std::string error = ErrorOf([&] { EstimateIntrinsics(folder, plan); });
  EXPECT_NE(error.find("need the board in at least 3 photographs; 2 of 4 show it"), std::string::npos) << error;
  EXPECT_NE(error.find("\n  missing.exr: "), std::string::npos) << error;
  EXPECT_NE(error.find("\n  notes.txt: "), std::string::npos) << error;
}

TEST(CameraIntrinsicsTest, TheCameraFileKeepsTheUncertaintyAndReadsItStrictly) {
  CameraIntrinsics estimated{431.25, 436.5, 243.125, 176.75, -0.0493, 0.0187, std::nullopt};
  estimated.uncertainty = CameraIntrinsicsUncertainty{0.371, 0.376, 0.166, 0.206, 0.00232, 0.00826, 0.106};
  const nlohmann::json written = CameraIntrinsicsToJson(estimated);
  const CameraIntrinsics read = ReadCameraIntrinsics(Params(written, {"camera.json", ""}));
  ASSERT_TRUE(read.uncertainty);
  EXPECT_DOUBLE_EQ(read.fx, estimated.fx);
  EXPECT_DOUBLE_EQ(read.k2, estimated.k2);
  EXPECT_DOUBLE_EQ(read.uncertainty->fx_px, 0.371);
  EXPECT_DOUBLE_EQ(read.uncertainty->cy_px, 0.206);
  EXPECT_DOUBLE_EQ(read.uncertainty->k1, 0.00232);
  EXPECT_DOUBLE_EQ(read.uncertainty->k2, 0.00826);
  EXPECT_DOUBLE_EQ(read.uncertainty->rms_reprojection_px, 0.106);
  // The file `detect --camera` reads.
  const std::string path = FreshFolder("camera_file") + "/camera.json";
  { std::ofstream(path) << written.dump(2); }
  EXPECT_DOUBLE_EQ(ReadCameraIntrinsicsFile(path).cy, estimated.cy);
  EXPECT_DOUBLE_EQ(ReadCameraIntrinsicsFile(path).uncertainty->cx_px, 0.166);

  auto error = [](nlohmann::json camera) {
    return ErrorOf([&] { ReadCameraIntrinsics(Params(camera, {"camera.json", ""})); });
  };
  nlohmann::json partial = written;
  partial.erase("k2_std");
  EXPECT_NE(error(partial).find("without \"k2_std\""), std::string::npos) << error(partial);
  nlohmann::json negative = written;
  negative["cx_std_px"] = -0.1;
  EXPECT_NE(error(negative).find("camera.json: /cx_std_px: a standard deviation"), std::string::npos)
      << error(negative);
  nlohmann::json misspelled = written;
  misspelled["fy_std_pix"] = misspelled["fy_std_px"];
  misspelled.erase("fy_std_px");
  EXPECT_NE(error(misspelled).find("fy_std_px"), std::string::npos) << error(misspelled);
}

TEST(CameraIntrinsicsTest, ThePlanReadsBackAndIsReadStrictly) {
  CameraPlanOptions options;
  options.squares_x = 9;
  options.squares_y = 6;
  options.square_m = 0.025;
  options.poses = 14;
  const CameraCapturePlan plan = PlanCameraCaptures(options);
  ASSERT_EQ(plan.photos.size(), 14u);
  // Every pose tilted 20 to 40 deg about one axis or both, never face-on.
  for (const PlannedBoardPhoto& p : plan.photos) {
    const double largest = std::max(std::abs(p.tilt_rad[0]), std::abs(p.tilt_rad[1])) * kDegreesPerRadian;
    EXPECT_GE(largest, 20 - 1e-9) << p.photo;
    EXPECT_LE(largest, 40 + 1e-9) << p.photo;
  }
  const nlohmann::json document = nlohmann::json::parse(CameraCapturePlanToJson(plan).dump());
  const CameraCapturePlan read = ParseCameraCapturePlan(document, "camera_captures.json");
  EXPECT_EQ(read.board.squares_x, 9);
  EXPECT_DOUBLE_EQ(read.board.square_m, 0.025);
  ASSERT_EQ(read.photos.size(), 14u);
  for (size_t k = 0; k < read.photos.size(); ++k) {
    EXPECT_EQ(read.photos[k].photo, plan.photos[k].photo);
    EXPECT_NEAR(read.photos[k].tilt_rad[0], plan.photos[k].tilt_rad[0], 1e-3);
    EXPECT_NEAR(read.photos[k].tilt_rad[1], plan.photos[k].tilt_rad[1], 1e-3);
    EXPECT_EQ(read.photos[k].advice, plan.photos[k].advice);
  }
  auto error = [](const nlohmann::json& doc) { return ErrorOf([&] { ParseCameraCapturePlan(doc, "p.json"); }); };
  nlohmann::json misspelled = document;
  misspelled["photos"][3]["tilts"] = misspelled["photos"][3]["tilt"];
  EXPECT_NE(error(misspelled).find("p.json: /photos/3/tilts"), std::string::npos) << error(misspelled);
  EXPECT_NE(error(misspelled).find("\"tilt\""), std::string::npos) << error(misspelled);
  nlohmann::json format = document;
  format["format"] = "layerlab-captures/1";
  EXPECT_NE(error(format).find("p.json: /format: unknown camera capture plan format"), std::string::npos)
      << error(format);
  nlohmann::json square = document;
  square["board"]["squares"] = {7, 7};
  EXPECT_NE(error(square).find("p.json: /board/squares"), std::string::npos) << error(square);
  nlohmann::json twice = document;
  twice["photos"][1]["photo"] = twice["photos"][0]["photo"];
  EXPECT_NE(error(twice).find("/photos/1/photo: \"board_01.png\" is named twice"), std::string::npos) << error(twice);
  CameraPlanOptions huge;
  huge.squares_x = 1000;
  huge.squares_y = 999;
  const std::string too_large = ErrorOf([&] { PlanCameraCaptures(huge); });
  EXPECT_NE(too_large.find("--squares 1000 999: the board's image would have 100200 x 100100 pixels"),
            std::string::npos)
      << too_large;
  nlohmann::json steep = document;
  steep["photos"][0]["tilt"] = {"70 deg", "0 deg"};
  EXPECT_NE(error(steep).find("/photos/0/tilt: tilts of up to 60 deg"), std::string::npos) << error(steep);
}

// The image to print: one square of white margin, then the squares, the top-left one dark.
TEST(CameraIntrinsicsTest, ThePrintedBoardHasItsMarginAndItsDarkTopLeftSquare) {
  PrintedChessboard board;
  board.squares_x = 5;
  board.squares_y = 4;
  board.pixels_per_square = 10;
  const std::vector<uint8_t> image = PrintedChessboardImage(board);
  ASSERT_EQ(image.size(), size_t{70 * 60});
  auto at = [&](int col, int row) { return image[static_cast<size_t>(row) * 70 + col]; };
  EXPECT_EQ(at(5, 5), 255);    // margin
  EXPECT_EQ(at(15, 15), 0);    // square (0, 0)
  EXPECT_EQ(at(25, 15), 255);  // square (1, 0)
  EXPECT_EQ(at(25, 25), 0);    // square (1, 1)
  EXPECT_EQ(at(55, 45), 255);  // square (4, 3)
  EXPECT_EQ(at(65, 55), 255);  // margin
}

}  // namespace
}  // namespace layerlab

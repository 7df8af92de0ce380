// The eye that moves: the pupil's place against the rotation geometry, the
// retina of a moved eye against the parallax of a plane, the pose's limits,
// and the eyebox map.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "layerlab/analysis/eyebox_map.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/systems/eye_pose_limits.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::CompileError;
using testing::CompileJson;
using testing::ElementNamed;

constexpr double kDeg = std::numbers::pi / 180;

// The turned eye built independently: the centre of rotation r behind the
// primary pupil, turned by the Fick rotation R = Ry(right) Rx(-up) (Eigen).
Eigen::Matrix3d Fick(double right, double up) {
  return (Eigen::AngleAxisd(right, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(-up, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

TEST(EyePose, PupilTurnsAboutTheCentreOfRotation) {
  EyePose pose;
  pose.gaze_rad = {10 * kDeg, 0};
  const Vector3 c = PupilCenter(pose);
  // 10 deg of gaze at 10 mm: r sin 10 deg = 1.7365 mm across, r (1 - cos 10 deg) = 0.1519 mm back.
  EXPECT_NEAR(c[0], 1.7364817766693033e-3, 1e-15);
  EXPECT_NEAR(c[1], 0, 1e-18);
  EXPECT_NEAR(c[2], -1.5192246987791975e-4, 1e-15);
  for (double right : {-20.0, 0.0, 7.5, 30.0})
    for (double up : {-15.0, 0.0, 12.0}) {
      pose.gaze_rad = {right * kDeg, up * kDeg};
      pose.pupil_offset_m = {0.7e-3, -0.4e-3};
      pose.rotation_radius_m = 0.011;
      const Eigen::Matrix3d R = Fick(right * kDeg, up * kDeg);
      const Eigen::Vector3d centre_of_rotation(0.7e-3, -0.4e-3, -0.011);
      const Eigen::Vector3d g = R * Eigen::Vector3d::UnitZ();
      const Vector3 gaze = GazeDirection(pose);
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(gaze[a], g[a], 1e-15);
      for (double u_x : {-2e-3, 0.0, 1.5e-3})
        for (double u_y : {-1e-3, 0.0, 2e-3}) {
          const Eigen::Vector3d expected = centre_of_rotation + R * Eigen::Vector3d(u_x, u_y, 0.011);
          const Vector3 p = PupilPointAt(pose, u_x, u_y);
          for (int a = 0; a < 3; ++a) ASSERT_NEAR(p[a], expected[a], 1e-15) << right << " " << up;
          // Carried along the gaze to the eye plane: the line p + s g at z = 0.
          const Eigen::Vector3d on = expected - expected.z() / g.z() * g;
          const std::array<double, 2> q = OnEyePlane(pose, u_x, u_y);
          ASSERT_NEAR(q[0], on.x(), 1e-15);
          ASSERT_NEAR(q[1], on.y(), 1e-15);
        }
    }
}

// The first-order placement of a turned pupil (elements/eye_pose.h), against
// the exact ray from the pupil point in 3-D to the in-focus point: both aim
// at it, so where they read a layer of D diopters differs by |D - D_a| times
// the shift of their crossings of the eye plane, depth x |tan(ray) - tan(gaze)|
// (docs/eye-pose.md's table): none along the gaze.
TEST(EyePose, ATurnedPupilIsExactAlongTheGazeAndWithinTheBoundOffIt) {
  EyePose pose;
  const double accommodation = 1.3, z_a = 1 / accommodation;
  for (const double gaze_deg : {5.0, 15.0}) {
    pose.gaze_rad = {gaze_deg * kDeg, 0};
    const Vector3 g = GazeDirection(pose);
    const std::array<double, 2> c = OnEyePlane(pose, 0, 0);
    for (const double psi_deg : {0.0, 10.0})
      for (const double u_x : {-2e-3, 0.0, 2e-3})
        for (const double D : {0.4, 2.6}) {
          const double t = std::tan((gaze_deg + psi_deg) * kDeg);  // the retinal direction, in the display's tan
          const Vector3 P = PupilPointAt(pose, u_x, 0);
          const Eigen::Vector3d F(c[0] + z_a * t, 0, z_a), p(P[0], P[1], P[2]);
          // Exact: the line P -> F at depth 1/D, in tan units.
          const Eigen::Vector3d exact = p + (1 / D - p.z()) / (F.z() - p.z()) * (F - p);
          // First order: from the carried point on the eye plane toward F.
          const std::array<double, 2> x0 = OnEyePlane(pose, u_x, 0);
          const double first = x0[0] + (1 / D) * (F.x() - x0[0]) / z_a;
          const double slope = (F.x() - p.x()) / (F.z() - p.z());
          const double bound = std::abs(D - accommodation) * std::abs(p.z()) * std::abs(slope - g[0] / g[2]);
          const double error = std::abs(exact.x() - first) * D;
          EXPECT_NEAR(error, bound, 1e-12 + 1e-9 * bound) << gaze_deg << " deg, " << psi_deg << " off, u " << u_x;
          if (psi_deg == 0 && u_x == 0) {
            EXPECT_LT(error, 1e-15);
          }
        }
  }
}

TEST(EyePose, GazeCentresTheRetinaAndPlacesThePupilSamples) {
  EyeModel eye;
  eye.pose.gaze_rad = {12 * kDeg, -5 * kDeg};
  eye.pose.pupil_offset_m = {0.5e-3, 0.25e-3};
  const RetinaGrid grid = CenteredOnGaze(MakeRetinaGrid(0.1, 0.1, 0.01), eye.pose);
  const Vector3 g = GazeDirection(eye.pose);
  EXPECT_NEAR(std::tan(grid.center_x_rad), g[0] / g[2], 1e-15);
  EXPECT_NEAR(std::tan(grid.center_y_rad), g[1] / g[2], 1e-15);
  EyeModel ahead;
  const std::vector<PupilPoint> own = PupilSamples(ahead), turned = PupilSamples(eye);
  ASSERT_EQ(own.size(), turned.size());
  const std::array<double, 2> centre = OnEyePlane(eye.pose, 0, 0);
  for (size_t k = 0; k < own.size(); ++k) {
    const std::array<double, 2> at = OnEyePlane(eye.pose, own[k].x_m, own[k].y_m);
    EXPECT_EQ(turned[k].x_m, at[0]);
    EXPECT_EQ(turned[k].y_m, at[1]);
    EXPECT_EQ(turned[k].center_x_m, centre[0]);
    EXPECT_EQ(turned[k].center_y_m, centre[1]);
    EXPECT_EQ(own[k].center_x_m, 0.0);
  }
}

// A one-panel display at `depth` with a pattern of unequal pixels.
testing::OneLayer OneLayerDisplay(const std::string& depth) {
  testing::OneLayer d = testing::OneLayerDisplay(depth);
  for (size_t k = 0; k < d.t[0].rgb.size(); ++k) d.t[0].rgb[k] = 0.05f + 0.9f * float((k * 2654435761u) % 997) / 997;
  return d;
}

// A plane seen from a moved eye is the same picture moved by its parallax:
// the eye at c reads the plane of D diopters at tan + c D, at any focus. So
// the retina at pupil offset c is the centred one shifted by c D / resolution
// samples (a whole number here), identical sample for sample.
TEST(EyePose, APlaneLooksTheSameFromAcrossTheEyeboxUpToItsParallax) {
  testing::OneLayer d = OneLayerDisplay("2.0 D");
  const double D = 2.0, resolution = 0.02 * kDeg;
  const RetinaGrid retina = MakeRetinaGrid(6 * kDeg, 4 * kDeg, resolution);
  for (const double focus : {2.0, 0.7}) {
    const Image centred = RetinaOfDisplay(*d.model, d.t, retina, PupilSamples(d.system.eye), {focus, focus, focus});
    for (const int shift : {-3, 5}) {
      EyeModel eye = d.system.eye;
      // A shift of whole samples at the grid's centre: tan(c D) is not linear, so the test compares near the
      // centre, where tan(a + s) - tan(a) = s to 1e-4 of a sample.
      eye.pose.pupil_offset_m = {std::tan(shift * resolution) / D, 0};
      const Image moved = RetinaOfDisplay(*d.model, d.t, retina, PupilSamples(eye), {focus, focus, focus});
      int compared = 0, differing = 0;
      for (int i = retina.rows / 2 - 10; i < retina.rows / 2 + 10; ++i)
        for (int j = retina.cols / 2 - 10; j < retina.cols / 2 + 10; ++j)
          for (int c = 0; c < 3; ++c) {
            ++compared;
            differing += moved.at(i, j, c) != centred.at(i, j + shift, c);
          }
      // A ray on a pixel edge may round to either neighbour: 1 in 1000.
      EXPECT_LE(differing, compared / 1000) << "focus " << focus << " D, shift " << shift;
    }
  }
}

// A point on a layer does not swim in an ideal display: seen from any pupil
// position with the eye on its layer, it stays where a point at the layer's
// depth would be: its retinal centroid moves by -c D exactly (tan units).
TEST(EyePose, APointOnAnIdealLayerDoesNotSwim) {
  testing::OneLayer d = OneLayerDisplay("1.25 D");
  const double D = 1.25;
  for (float& v : d.t[0].rgb) v = 0;
  const int col = 40, row = 20;
  for (int c = 0; c < 3; ++c) d.t[0].rgb[(size_t(row) * 64 + col) * 3 + c] = 1;
  const RetinaGrid retina = MakeRetinaGrid(10 * kDeg, 8 * kDeg, 0.004 * kDeg);
  auto centroid = [&](const EyeModel& eye) {
    const Image image = RetinaOfDisplay(*d.model, d.t, retina, PupilSamples(eye), {D, D, D});
    double sum = 0, x = 0, y = 0;
    for (int i = 0; i < retina.rows; ++i)
      for (int j = 0; j < retina.cols; ++j) {
        const double w = image.at(i, j, 1);
        sum += w, x += w * std::tan(retina.angle_x(j)), y += w * std::tan(retina.angle_y(i));
      }
    return std::array<double, 2>{x / sum, y / sum};
  };
  const std::array<double, 2> centred = centroid(d.system.eye);
  for (const std::array<double, 2> c : {std::array<double, 2>{1.3e-3, 0}, {-0.9e-3, 0.6e-3}}) {
    EyeModel eye = d.system.eye;
    eye.pose.pupil_offset_m = c;
    const std::array<double, 2> moved = centroid(eye);
    // The pixel's footprint is resolved in samples of 0.004 deg: its centroid to a sample's width.
    for (int a = 0; a < 2; ++a) EXPECT_NEAR(moved[a] - centred[a], -c[a] * D, 0.004 * kDeg) << "axis " << a;
  }
}

// Two eyes 63 mm apart fixating a point 0.5 m ahead on the midline, by hand:
// each centre of rotation 10 mm behind its pupil turns atan(31.5 / 510) =
// 3.53437 deg inward; the vergence is twice that, the demand 1 / 0.5 m = 2 D.
// Off the midline each gaze points from its centre of rotation at the point
// (checked by cross products, apart from the Fick angles), and the scene's
// binocular key places and turns the eye so.
TEST(EyePose, TwoEyesVergeOnTheFixatedPoint) {
  Binocular pair;
  pair.ipd_m = 0.063, pair.fixation_m = {0, 0, 0.5};
  const double inward = std::atan(0.0315 / 0.51);
  EXPECT_NEAR(inward / kDeg, 3.53437, 5e-6);
  pair.side = -1;
  const EyePose left = FixatingPose(pair, 0.010);
  pair.side = 1;
  const EyePose right = FixatingPose(pair, 0.010);
  EXPECT_NEAR(left.gaze_rad[0], inward, 1e-15);
  EXPECT_NEAR(right.gaze_rad[0], -inward, 1e-15);
  EXPECT_EQ(left.pupil_offset_m[0], -0.0315);
  EXPECT_NEAR(VergenceAngle(pair, 0.010), 2 * inward, 1e-15);
  EXPECT_NEAR(VergenceDiopters(pair), 2.0, 1e-15);
  pair.fixation_m = {0.1, 0.05, 0.4};
  for (const bool shared : {true, false})
    for (const int side : {-1, 1}) {
      pair.side = side, pair.shared_display = shared;
      const EyePose pose = FixatingPose(pair, 0.012);
      const Eigen::Vector3d q(0.5 * side * 0.063, 0, -0.012), f(0.1, 0.05, 0.4);
      const Vector3 g = GazeDirection(pose);
      const Eigen::Vector3d towards = (f - q).normalized();
      EXPECT_NEAR(Eigen::Vector3d(g[0], g[1], g[2]).cross(towards).norm(), 0, 1e-15);
      EXPECT_GT(towards.dot(Eigen::Vector3d(g[0], g[1], g[2])), 0);
      EXPECT_EQ(pose.pupil_offset_m[0], shared ? 0.5 * side * 0.063 : 0.0);
    }
  const Eigen::Vector3d l = (Eigen::Vector3d(0.1, 0.05, 0.4) - Eigen::Vector3d(-0.0315, 0, -0.012)).normalized();
  const Eigen::Vector3d r = (Eigen::Vector3d(0.1, 0.05, 0.4) - Eigen::Vector3d(0.0315, 0, -0.012)).normalized();
  EXPECT_NEAR(VergenceAngle(pair, 0.012), std::acos(l.dot(r)), 1e-12);

  nlohmann::json scene = testing::ShrunkExample("paper_prototype.json", 400, 240, 3);
  ElementNamed(scene, "eye")["binocular"] = {
      {"side", "right"}, {"ipd", "63 mm"}, {"fixation", {"0 mm", "0 mm", "0.5 m"}}};
  const DisplaySystem system = CompileJson(scene);
  ASSERT_TRUE(system.eye.binocular);
  EXPECT_NEAR(system.eye.pose.gaze_rad[0], -inward, 1e-15);
  EXPECT_EQ(system.eye.pose.pupil_offset_m[0], 0.0315);
  ElementNamed(scene, "eye")["gaze"] = {"1 deg", "0 deg"};
  EXPECT_NE(CompileError(scene).find("not with \"binocular\""), std::string::npos) << CompileError(scene);
  ElementNamed(scene, "eye").erase("gaze");
  ElementNamed(scene, "eye")["binocular"]["sid"] = "left";
  EXPECT_NE(CompileError(scene).find("sid"), std::string::npos) << CompileError(scene);
}

// The other eye of a pair is its mirror image across the midline: its side,
// offset and horizontal gaze flipped (a symmetric fixation), and where the
// pair's frame lies in each eye's display frame: nowhere else for a shared
// display, ipd / 2 toward the midline for a display of its own (a point on
// the midline lies 31.5 mm right of the left eye's axis).
TEST(EyePose, ThePartnerIsTheMirrorImageAndTheFrameFollowsTheDisplay) {
  for (const char* display : {"shared", "own"}) {
    nlohmann::json scene = testing::ShrunkExample("paper_prototype.json", 400, 240, 3);
    ElementNamed(scene, "eye")["binocular"] = {
        {"side", "left"}, {"ipd", "63 mm"}, {"display", display}, {"fixation", {"0 mm", "20 mm", "0.5 m"}}};
    const EyeModel left = CompileJson(scene).eye;
    const EyeModel right = PartnerEye(left);
    ASSERT_TRUE(right.binocular);
    EXPECT_EQ(right.binocular->side, 1);
    EXPECT_EQ(right.pose.pupil_offset_m[0], -left.pose.pupil_offset_m[0]) << display;
    EXPECT_NEAR(right.pose.gaze_rad[0], -left.pose.gaze_rad[0], 1e-15) << display;
    EXPECT_NEAR(right.pose.gaze_rad[1], left.pose.gaze_rad[1], 1e-15) << display;
    EXPECT_GT(left.pose.gaze_rad[1], 0);
    EXPECT_EQ(PartnerEye(right).pose.gaze_rad, left.pose.gaze_rad);
    const bool shared = std::string(display) == "shared";
    EXPECT_EQ(PairFrameInDisplayFrame(*left.binocular), (Vector3{shared ? 0.0 : 0.0315, 0, 0})) << display;
    EXPECT_EQ(PairFrameInDisplayFrame(*right.binocular), (Vector3{shared ? 0.0 : -0.0315, 0, 0})) << display;
  }
  EXPECT_EQ(testing::ErrorOf([] { PartnerEye(EyeModel{}); }),
            "the scene's eye is not one of a binocular pair (its \"binocular\" key)");
}

TEST(EyePose, LimitsNameWhatTheyRefuse) {
  nlohmann::json scene = testing::ShrunkExample("paper_prototype.json", 400, 240, 3);  // a field of 36 x 22 deg
  ElementNamed(scene, "eye")["gaze"] = {"40 deg", "0 deg"};
  const std::string error = CompileError(scene);
  EXPECT_NE(error.find("/gaze"), std::string::npos) << error;
  EXPECT_NE(error.find("40.00 deg right is beyond the display's field"), std::string::npos) << error;
  ElementNamed(scene, "eye")["gaze"] = {"51 deg", "0 deg"};
  EXPECT_NE(CompileError(scene).find("gaze"), std::string::npos);
  ElementNamed(scene, "eye")["gaze"] = {"5 deg", "0 deg"};
  ElementNamed(scene, "eye")["pupil_offset"] = {"1.5 mm", "0 mm"};
  const DisplaySystem system = CompileJson(scene);
  // 5 deg turns the pupil r tan(5 deg) = 0.875 mm on the eye plane: with the offset and a 2 mm half pupil
  // carried there (2 mm / cos 5 deg = 2.0076 mm) the pupil reaches 4.383 mm of the eyebox's 3 mm.
  ASSERT_FALSE(system.warnings.empty());
  bool named = false;
  for (const std::string& w : system.warnings)
    named = named || w.find("4.383 mm from the axis in x") != std::string::npos;
  EXPECT_TRUE(named) << system.warnings.back();
  EyeModel inside = system.eye;
  inside.pose = EyePose{};
  inside.pose.pupil_offset_m = {1e-3, -1e-3};
  EXPECT_EQ(PupilBeyondEyebox(inside), "");
  inside.pose.pupil_offset_m = {1.01e-3, 0};
  EXPECT_NE(PupilBeyondEyebox(inside), "");
}

// The eyebox within a PSNR drop, on a hand-made grid: the run through the centre along each axis.
TEST(EyeboxMap, TheEyeboxIsTheRunThroughTheCentreWithinTheDrop) {
  EyeboxGrid g;
  g.cols = 5, g.rows = 3, g.step = 1e-3;
  const double psnr[3][5] = {{20, 29.5, 29.2, 29, 28}, {28.9, 29.1, 30, 29.05, 29.5}, {30, 30, 28.5, 30, 30}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 5; ++j) {
      EyeboxPoseResult r;
      r.psnr_db = psnr[i][j];
      g.poses.push_back(r);
    }
  // Centre 30 dB; within 1 dB along the middle row: columns 1 .. 4 (column 0 has 28.9); along the middle
  // column: row 0 (29.2) but not row 2 (28.5).
  EXPECT_DOUBLE_EQ(g.within(1.0)[0], 3e-3);
  EXPECT_DOUBLE_EQ(g.within(1.0)[1], 1e-3);
  EXPECT_FALSE(g.within_reaches_edge(1.0)[0]);
  EXPECT_DOUBLE_EQ(g.within(1.2)[0], 4e-3);
  EXPECT_TRUE(g.within_reaches_edge(1.2)[0]);
  EXPECT_DOUBLE_EQ(g.within(1.6)[1], 2e-3);
}

// Each pose's PSNR is that of its own two retinal images, made here the
// long way; the centre's brightness ratio is 1; a light-field target is
// refused where the pupil leaves its eyebox, with the limit named.
TEST(EyeboxMap, EachPoseComparesItsOwnRetinalImages) {
  testing::OneLayer d = OneLayerDisplay("1.0 D");
  // The target: the layer's plane with a brighter band, seen from any pupil (a traced target's role).
  const VirtualLayer& layer = d.system.layers[0];
  const SceneRadiance plane = [&](const PupilPoint& u, double dx, double dy) {
    const double x = u.x_m + dx / layer.diopters, y = u.y_m + dy / layer.diopters;
    const double v = std::abs(x) < 0.01 ? 0.8 : 0.3 + 0.1 * std::sin(300 * y);
    return std::array<double, 3>{v, v, v};
  };
  EyeboxMapOptions o;
  o.accommodation_diopters = 0.5;
  o.pupil_half_range_m = {2e-3, 1e-3};
  o.pupil_step_m = 1e-3;
  o.gaze_half_range_rad = {2 * kDeg, 0};
  o.gaze_step_rad = 2 * kDeg;
  o.gaze_field_deg = {4, 3};
  o.resolution_deg = 0.1;
  const EyeboxMap map = MapEyebox(*d.model, d.t, plane, o);
  ASSERT_EQ(map.pupil.cols, 5);
  ASSERT_EQ(map.pupil.rows, 3);
  ASSERT_EQ(map.gaze.cols, 3);
  ASSERT_EQ(map.gaze.rows, 1);
  EXPECT_EQ(map.pupil.centre().brightness_ratio, 1.0);
  EXPECT_EQ(map.pupil.centre().vignetting, 0.0);
  const EyeboxPoseResult& corner = map.pupil.poses[2 * 5 + 4];  // bottom right: +2 mm, -1 mm
  EXPECT_DOUBLE_EQ(corner.pose.pupil_offset_m[0], 2e-3);
  EXPECT_DOUBLE_EQ(corner.pose.pupil_offset_m[1], -1e-3);
  for (const EyeboxPoseResult* r : {&corner, &map.gaze.poses[0]}) {
    EyeModel eye = d.system.eye;
    eye.pose = r->pose;
    const bool turned = !r->pose.straight_ahead();
    RetinaGrid grid = turned ? CenteredOnGaze(MakeRetinaGrid(4 * kDeg, 3 * kDeg, 0.1 * kDeg), eye.pose)
                             : MakeRetinaGrid(d.system.fov_x_rad, d.system.fov_y_rad, 0.1 * kDeg);
    const std::vector<PupilPoint> pupil = PupilSamples(eye);
    const Image shown = RetinaOfDisplay(*d.model, d.t, grid, pupil, {0.5, 0.5, 0.5});
    const Image seen = RetinaOfSceneRayByRay(plane, grid, pupil, {0.5, 0.5, 0.5});
    double sum = 0;
    for (size_t k = 0; k < shown.pixels.size(); ++k) sum += std::pow(double(shown.pixels[k]) - seen.pixels[k], 2);
    EXPECT_NEAR(r->psnr_db, 10 * std::log10(shown.pixels.size() / sum), 1e-3) << (turned ? "gaze" : "pupil");
  }
  // A light field holds its rays across its 6 mm eyebox only: a 4 mm pupil may move 1 mm.
  const LightFieldGeometry g = DisplayLightFieldGeometry(d.system, 1.0);
  LightField lf(g);
  std::fill(lf.rgb.begin(), lf.rgb.end(), 0.5f);
  o.gaze_half_range_rad = {0, 0};
  try {
    MapEyebox(*d.model, d.t, LightFieldRadiance(lf), o);
    ADD_FAILURE() << "a pupil beyond the light field's eyebox was mapped";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--eyebox-range: at a pupil offset of -2.000, 1.000 mm the pupil reaches 4.000 mm"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("stays inside up to 1.000 mm"), std::string::npos) << m;
  }
  o.pupil_half_range_m = {1e-3, 1e-3};
  EXPECT_NO_THROW(MapEyebox(*d.model, d.t, LightFieldRadiance(lf), o));
}

// The moved and turned eye in natural viewing of a light field: image-wise
// as ray by ray (the display's paths: Retina.FastAndGeneralPathsAgree).
TEST(EyePose, ALightFieldIsSeenAlikeImageWiseAndRayByRay) {
  const DisplaySystem system = CompileJson(testing::ShrunkExample("paper_prototype.json", 40, 24, 3));
  const RetinaGrid retina = MakeRetinaGrid(system.fov_x_rad * 0.6, system.fov_y_rad * 0.6, system.fov_x_rad / 120);
  EyeModel eye = system.eye;
  eye.pose.pupil_offset_m = {0.4e-3, -0.3e-3};
  eye.pose.gaze_rad = {0.3 * kDeg, -0.2 * kDeg};
  const std::vector<PupilPoint> pupil = PupilSamples(eye);
  const LightField lf = testing::RandomLightField(DisplayLightFieldGeometry(system), 5);
  for (const double focus : {0.0, 1.1}) {
    const Image image_wise = RetinaOfScene(LightFieldRadiance(lf), retina, pupil, {focus, focus, focus});
    const Image ray_by_ray = RetinaOfSceneRayByRay(LightFieldRadiance(lf), retina, pupil, {focus, focus, focus});
    const Image centred =
        RetinaOfScene(LightFieldRadiance(lf), retina, PupilSamples(system.eye), {focus, focus, focus});
    double worst = 0, moved = 0;
    for (size_t k = 0; k < image_wise.pixels.size(); ++k) {
      worst = std::max(worst, double(std::abs(image_wise.pixels[k] - ray_by_ray.pixels[k])));
      moved = std::max(moved, double(std::abs(image_wise.pixels[k] - centred.pixels[k])));
    }
    EXPECT_LT(worst, 1e-5) << "focus " << focus;
    EXPECT_GT(moved, 0.05) << "the pose changed the picture";
  }
}

}  // namespace
}  // namespace layerlab

// Where the eye is and where it looks: a pupil that moves with the wearer's
// fit and turns with the gaze.
//
// Frame: the eye plane is the pupil plane of the eye looking straight ahead
// at its eye relief; x right, y up, z toward the display. The eye turns about
// its centre of rotation, `rotation_radius_m` behind the pupil centre, by Fick
// angles: gaze[0] about the vertical axis (right positive), then gaze[1] about
// the turned horizontal axis (up positive). Its pupil centre then lies at
//   C = (offset_x, offset_y, -r) + r g,   g = (sin gx cos gy, sin gy, cos gx cos gy),
// so it moves r sin(10 deg) = 1.74 mm for 10 deg of gaze at r = 10 mm, and back
// from the display by r (1 - cos g).
//
// The retina (retina/retina.h) describes every ray by where it crosses the
// eye plane and its tan-direction. A point of the turned pupil is carried
// there along the gaze: exact for rays along the gaze, and for a ray psi off
// it wrong by (its distance from the eye plane) x (tan(g + psi) - tan g) in
// the eye plane (docs/eye-pose.md bounds it). The eye accommodates to a plane
// parallel to the display, so a layer it accommodates to is sharp at any gaze.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace layerlab {

// The limits a scene's pose is read within: a fit, a physiological gaze, an eye.
inline constexpr double kMaxPupilOffset = 0.05;         // m
inline constexpr double kMaxGaze = 0.8726646259971648;  // rad, 50 deg
inline constexpr double kMaxRotationRadius = 0.03;      // m

using Vector3 = std::array<double, 3>;

struct EyePose {
  std::array<double, 2> pupil_offset_m = {0, 0};  // m, the centre of rotation's move across the eye plane (x, y)
  std::array<double, 2> gaze_rad = {0, 0};        // rad, Fick angles: right, then up
  double rotation_radius_m = 0.010;               // m, pupil centre to the eye's centre of rotation
  bool straight_ahead() const { return gaze_rad[0] == 0 && gaze_rad[1] == 0; }
};

// One of a pair of eyes `ipd_m` apart whose pupils lie on the eye plane, the
// frame's origin midway between them, turned to look at a fixated point.
// A direct-view display seen by both (`shared_display`) has its axis on the
// midline, so the eye sits at x = -ipd/2 (left) or +ipd/2 (right); a
// near-eye display has one display per eye on that eye's axis, so the eye
// sits on it (no offset). Either way the eye turns about its centre of
// rotation Q = (x_eye, 0, -r) toward the fixation F: g = (F - Q) / |F - Q|.
struct Binocular {
  double ipd_m = 0.063;
  int side = -1;  // -1 left, +1 right
  bool shared_display = true;
  Vector3 fixation_m = {0, 0, 0.5};  // m, from the midpoint between the pupils
};

// A square grid of pupil offsets (m) within `range_m` of the centre in x and
// y, `step_m` apart (0: the range, so 3 x 3), row by row from the lowest y,
// x rising; empty for a zero range. EyeboxGridSize is its length, (2 n + 1)^2
// with n the whole steps within the range, known before it is made.
// EyeboxGridOffsets refuses a grid of more than kMaxEyeboxGridSize.
inline constexpr int kMaxEyeboxGridSize = 10000;
double EyeboxGridSize(double range_m, double step_m);
std::vector<std::array<double, 2>> EyeboxGridOffsets(double range_m, double step_m);
// "" when the options eyebox_range and eyebox_step describe a grid of at most `max_positions`; otherwise
// "eyebox_step: value: constraint" (framework/option_table.h OptionViolation), the count's with `why_limited`.
std::string EyeboxGridViolation(double range_m, double step_m, int max_positions, const std::string& why_limited = "");
// `pose` with its pupil moved across the eye plane by (dx, dy), m.
EyePose WithPupilMoved(EyePose pose, double dx_m, double dy_m);

// Where a point given in the pair's frame (from the midpoint between the
// pupils) lies in this eye's display frame is that point plus this, m: 0 for
// a shared display (its axis is the midline), -side ipd / 2 in x for a
// display of its own (its axis is the eye's). A target scene in the pair's
// frame is moved by it to be seen by this eye (targets rendered per eye).
Vector3 PairFrameInDisplayFrame(const Binocular& b);

// The eye's pose: its offset, and the Fick angles of g.
EyePose FixatingPose(const Binocular& b, double rotation_radius_m);
// The angle between the two eyes' gaze directions, rad.
double VergenceAngle(const Binocular& b, double rotation_radius_m);
// The vergence demand in diopters (metre angles): 1 / |F|, the fixation's
// distance from the midpoint between the pupils; the vergence-accommodation
// conflict of an eye accommodated to D is this minus D.
double VergenceDiopters(const Binocular& b);

// The gaze's unit direction g.
Vector3 GazeDirection(const EyePose& pose);
// The pupil's centre C, m, in the frame above.
Vector3 PupilCenter(const EyePose& pose);
// The point (u_x, u_y) of the pupil's own plane (m from its centre, along
// the turned x and y axes), in the frame above.
Vector3 PupilPointAt(const EyePose& pose, double u_x, double u_y);
// That point carried along the gaze onto the eye plane (z = 0), m.
std::array<double, 2> OnEyePlane(const EyePose& pose, double u_x, double u_y);

}  // namespace layerlab

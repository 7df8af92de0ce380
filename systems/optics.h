// First-order optics of a magnifier display (paper Eq. 1 and 2), as one case
// of the ray-transfer composition in systems/ray_transfer.h.
//
// A panel at distance s behind a thin lens of focal length f (0 < s <= f)
// forms an upright virtual image at d = s f / (f - s) behind the lens,
// magnified M = f / (f - s). With the pupil e in front of the lens the image
// sits at eye-space depth z = d + e, i.e. D = 1/z diopters. Everything is
// also expressed per unit of panel length seen from the eye: a panel length
// L subtends tan-angle L * M / z = L * f / (s f + e (f - s)), which stays
// finite when s -> f (the image at infinity, 0 D).
#pragma once

namespace layerlab {

struct FloatedImage {
  double diopters;          // 1/z, eye space; 0 when s == f
  double depth_m;           // z in m; +inf when s == f
  double image_distance_m;  // d in m, from the lens; +inf when s == f
  double magnification;     // M; +inf when s == f
  double tan_per_meter;     // tan-angle per meter of panel: M / z = M D
};

// Requires 0 < s <= f and e >= 0 (the caller reports violations).
FloatedImage FloatPanel(double s, double f, double e);

// The panel distance s that floats the image to `diopters` from the eye;
// requires 0 <= diopters < 1/e (an image beyond the lens toward the eye is impossible).
double PanelDistanceForDiopters(double diopters, double f, double e);

// Eq. 2 for a layer of `pixels` pixels of angular pitch `tan_pitch` (tan-angle
// per pixel), centered on the axis: 2 atan(n tan_pitch / 2), in radians.
double FieldOfView(double tan_pitch, double pixels);

// Highest angular frequency a pixel grid can carry at its center, in cycles
// per degree: one cycle per two pixels.
double NyquistCyclesPerDegree(double tan_pitch);

}  // namespace layerlab

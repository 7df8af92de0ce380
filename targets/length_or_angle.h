// Sizes of things at a known depth may be given as a length ("12 mm") or as
// the angle they subtend from the pupil center ("1 deg"). An angle a at depth
// z becomes a * z meters: linear on the plane, so that a grating of f cycles
// per degree has exactly f / (z * pi / 180) cycles per meter everywhere on it
// (the small-angle view; off axis the angle subtended shrinks as cos^2).
#pragma once

#include <array>
#include <string>

#include "layerlab/framework/params.h"

namespace layerlab {

// A length or an angle, in meters at `depth`; a bare number is ambiguous and refused.
double LengthOrAngle(Params& p, const std::string& key, double depth);
// [a, b], each a length or an angle, or one value for both.
std::array<double, 2> LengthOrAnglePair(Params& p, const std::string& key, double depth);

// Spatial frequency in cycles per meter on a plane at `depth` of `cpd` cycles per degree.
double CyclesPerMeter(double cpd, double depth);

}  // namespace layerlab

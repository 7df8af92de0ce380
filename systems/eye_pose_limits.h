// An eye's pose against the display it looks into: a gaze inside the
// display's field, a pupil inside the eyebox the light field covers.
#pragma once

#include <array>
#include <string>

#include "layerlab/elements/element.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

// The gaze direction's angle from the axis in x and y (as the retina's grid
// is centred, retina/retina_grid.h), rad: atan(g_x / g_z), atan(g_y / g_z).
std::array<double, 2> GazeAngles(const EyePose& pose);

// The other eye of a binocular pair (EyeModel::binocular): the same eye and
// pair, its side flipped, placed and turned toward the same fixation.
EyeModel PartnerEye(const EyeModel& eye);

// "" when the gaze points inside the display's field of view; otherwise a
// sentence naming the limit ("20.00 deg right is beyond the display's field,
// 17.75 deg either side of the axis").
std::string GazeBeyondField(const DisplaySystem& system, const EyePose& pose);

// How far the whole pupil (not its samples) reaches from the axis on the eye
// plane, m, in x and y.
std::array<double, 2> PupilReachOnEyePlane(const EyeModel& eye);

// "" when the pupil lies inside the eyebox; otherwise a sentence with the
// reach and the limit, and the largest offset that keeps this pupil inside.
std::string PupilBeyondEyebox(const EyeModel& eye);
// The same as a warning, with what it means: natural viewing of a light
// field reads its edge views there. "" inside the eyebox.
std::string PupilBeyondEyeboxWarning(const EyeModel& eye);

}  // namespace layerlab

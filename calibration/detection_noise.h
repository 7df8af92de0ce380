// How well one photograph's markers were found, measured without the display
// model: the scatter of a board's corners about a smooth map of the board.
//
// Whatever carries a flat board to the camera (the display's optics with
// their distortion, the panel's offset and rotation, the camera's pointing
// and undistortion) is a smooth map from panel pixels to visual angles. Over
// one board it is fitted per axis by a polynomial of total degree 3 in the
// panel pixel (10 coefficients), which follows projective maps and radial
// distortion of the orders real magnifiers show to far below a corner
// detector's noise; what it leaves is the detection's own error. Its mean
// square over the 2 (n - 10) degrees of freedom of n corners is the noise
// variance per axis. A display model that is right leaves no more than that
// (calibration.h's model-error test); a wrong one does, however many of its
// parameters absorb.
#pragma once

#include <optional>
#include <vector>

#include "layerlab/calibration/measurements.h"

namespace layerlab {

// The polynomial's coefficients per axis, and the fewest markers a board
// needs for an estimate (6 degrees of freedom per axis).
inline constexpr int kBoardNoiseTerms = 10;
inline constexpr int kBoardNoiseMinMarkers = kBoardNoiseTerms + 6;

// The noise of `markers` (one photograph of one panel's board), or nullopt
// when they are too few or do not span the board in two directions (on one
// line, or on fewer than 4 distinct rows or columns).
std::optional<DetectionNoise> EstimateBoardNoise(const std::vector<MarkerObservation>& markers);

}  // namespace layerlab

// Whether a found chessboard is the plan's board the way round the design
// predicts it, by the colour of its squares.
//
// The corners alone cannot tell: OpenCV finds them in any of four orders
// (as shown, mirrored left to right, top to bottom, turned by 180 degrees),
// which FindChessboardCorners orders by the prediction, and a board centred
// in its panel lies in the same place mirrored. Its squares can, as far as
// the square counts let them: square (i, j) is dark when i + j is even (the
// top-left one dark, Chessboard::dark), and a board of squares_x x squares_y
// squares read with its columns reversed (i -> squares_x - 1 - i) changes the
// colour of every square when squares_x - 1 is odd, i.e. squares_x is even.
// So, with squares_x != squares_y and both at least 4:
//   both even:     a mirror either way shows (the two differ by a 180-degree
//                  turn, which does not: a turned board is not caught);
//   x even, y odd: a mirror left to right and a 180-degree turn show, a
//                  mirror top to bottom does not;
//   x odd, y even: a mirror top to bottom and a 180-degree turn show, a
//                  mirror left to right does not;
//   both odd:      nothing shows (every corner square is dark): the board
//                  reads the same all four ways, and `detect` says so once.
// Wrong parity refuses the photograph with a reason that names the change.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "layerlab/calibration/capture_plan.h"

namespace layerlab {

// "" when the board whose inner corners are `corners` (camera pixels (u, v),
// row-major from the top left, ordered as the design predicts them) has the
// plan's dark squares dark in the photograph `pixels` (linear light,
// [row][col], width x height), or the square counts cannot show it;
// otherwise why the photograph is refused.
std::string BoardOrientationReason(const std::vector<float>& pixels, int width, int height, const Chessboard& board,
                                   const std::vector<std::array<double, 2>>& corners);

// What `detect` says once of a board whose orientation its colours cannot show (both counts odd); "" otherwise.
std::string UncheckedOrientationNote(const Chessboard& board);

}  // namespace layerlab

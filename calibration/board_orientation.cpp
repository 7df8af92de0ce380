#include "layerlab/calibration/board_orientation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace layerlab {
namespace {

using Pixel = std::array<double, 2>;

// The camera pixel of the middle of square (i, j) of the board: square i lies between inner corners i - 1 and
// i, so its middle is at corner coordinate i - 1/2, interpolated in the nearest cell of four found corners (and
// extrapolated by half a square for the squares along the edge). Also the local square size, in pixels.
std::pair<Pixel, double> SquareMiddle(const std::vector<Pixel>& corners, int cols, int rows, int i, int j) {
  const int a0 = std::clamp(i - 1, 0, cols - 2), b0 = std::clamp(j - 1, 0, rows - 2);
  const double s = i - 0.5 - a0, t = j - 0.5 - b0;
  const Pixel& p00 = corners[b0 * cols + a0];
  const Pixel& p10 = corners[b0 * cols + a0 + 1];
  const Pixel& p01 = corners[(b0 + 1) * cols + a0];
  const Pixel& p11 = corners[(b0 + 1) * cols + a0 + 1];
  Pixel middle;
  for (int k = 0; k < 2; ++k)
    middle[k] = (1 - s) * (1 - t) * p00[k] + s * (1 - t) * p10[k] + (1 - s) * t * p01[k] + s * t * p11[k];
  const double size =
      0.5 * (std::hypot(p10[0] - p00[0], p10[1] - p00[1]) + std::hypot(p01[0] - p00[0], p01[1] - p00[1]));
  return {middle, size};
}

// The mean of the photograph over a box of a fifth of a square about `middle` (pixel centres at integers);
// NaN when the box lies outside the photograph.
double MeanAround(const std::vector<float>& pixels, int width, int height, const Pixel& middle, double square_px) {
  const double half = std::max(0.0, 0.2 * square_px);
  const long u0 = std::max(0L, std::lround(middle[0] - half)),
             u1 = std::min<long>(width - 1, std::lround(middle[0] + half));
  const long v0 = std::max(0L, std::lround(middle[1] - half)),
             v1 = std::min<long>(height - 1, std::lround(middle[1] + half));
  double sum = 0;
  long n = 0;
  for (long v = v0; v <= v1; ++v)
    for (long u = u0; u <= u1; ++u, ++n) sum += pixels[static_cast<size_t>(v) * width + u];
  return n > 0 ? sum / static_cast<double>(n) : NAN;
}

}  // namespace

std::string BoardOrientationReason(const std::vector<float>& pixels, int width, int height, const Chessboard& board,
                                   const std::vector<Pixel>& corners) {
  const bool even_x = board.squares_x % 2 == 0, even_y = board.squares_y % 2 == 0;
  if (!even_x && !even_y) return "";
  const int cols = board.corners_x(), rows = board.corners_y();
  // The mean of the squares the plan has dark against those it has light, over the whole board.
  double dark_sum = 0, light_sum = 0;
  int dark_n = 0, light_n = 0;
  for (int j = 0; j < board.squares_y; ++j)
    for (int i = 0; i < board.squares_x; ++i) {
      const auto [middle, size] = SquareMiddle(corners, cols, rows, i, j);
      const double mean = MeanAround(pixels, width, height, middle, size);
      if (!std::isfinite(mean)) continue;
      const int64_t half = board.square_pixels / 2;
      if (board.dark(board.left + i * board.square_pixels + half, board.top + j * board.square_pixels + half))
        dark_sum += mean, ++dark_n;
      else
        light_sum += mean, ++light_n;
    }
  if (dark_n == 0 || light_n == 0 || dark_sum / dark_n < light_sum / light_n) return "";
  const std::string ask = ": was this photograph taken of another panel, or is the panel mounted ";
  if (even_x && even_y)
    return "mirrored board: its dark corner squares are at the top right and bottom left where the design puts "
           "them at the top left and bottom right (in the panel's pixel order)" +
           ask + "reversed?";
  if (even_x)
    return "mirrored or turned board: its dark corner squares are on the right where the design puts them on the "
           "left (in the panel's pixel order), as a board mirrored left to right or turned by 180 degrees shows" +
           ask + "reversed or upside down?";
  return "mirrored or turned board: its dark corner squares are at the bottom where the design puts them at the "
         "top (in the panel's pixel order), as a board mirrored top to bottom or turned by 180 degrees shows" +
         ask + "reversed or upside down?";
}

std::string UncheckedOrientationNote(const Chessboard& board) {
  if (board.squares_x % 2 == 0 || board.squares_y % 2 == 0) return "";
  return "panel \"" + board.panel + "\": a chessboard of " + std::to_string(board.squares_x) + " x " +
         std::to_string(board.squares_y) +
         " squares (both odd) reads the same mirrored or turned, so its photographs cannot show a mirrored, "
         "reversed or turned panel: plan an even number of squares across or down (e.g. --squares 10 6)";
}

}  // namespace layerlab

// The retina's samples: a planar grid indexed by visual angle (retina.h).
#pragma once

namespace layerlab {

struct RetinaGrid {
  int cols = 0, rows = 0;
  double resolution_rad = 0;                  // rad per sample, both axes
  double center_x_rad = 0, center_y_rad = 0;  // rad, the grid's center direction
  // Visual angle of sample column j (left to right) and row i (top to bottom).
  double angle_x(int j) const { return center_x_rad + (j + 0.5 - 0.5 * cols) * resolution_rad; }
  double angle_y(int i) const { return center_y_rad + (0.5 * rows - i - 0.5) * resolution_rad; }
};

}  // namespace layerlab

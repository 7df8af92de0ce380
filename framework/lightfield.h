// A light field in the two-plane parameterization of docs/lightfield-format.md:
// a ray passes v on the pupil plane (z = 0) and x on the origin plane (z = z_lf),
// p(z) = v + (x - v) z / z_lf. Views are pupil positions, cell-centered over
// the eyebox (row 0 at the top); pixels are origin-plane positions,
// cell-centered over the window (row 0 at the top). Values are linear RGB.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "layerlab/framework/huge_page_allocator.h"

namespace layerlab {

struct LightFieldGeometry {
  double origin_z_m = 1.0;  // z_lf, m
  double window_left_m = -0.5, window_top_m = 0.5, window_width_m = 1.0,
         window_height_m = 1.0;                          // m, on the origin plane
  int cols = 1, rows = 1;                                // pixels per view
  int views_x = 1, views_y = 1;                          // views per row, per column
  double eyebox_width_m = 6e-3, eyebox_height_m = 6e-3;  // m
  // A tile of a larger light field (one MPI rank's share): its views_y view
  // rows are rows first_view_row.. of all_view_rows over the whole
  // eyebox_height_m, and its `rows` pixel rows are rows first_pixel_row.. of
  // all_pixel_rows over the whole window_height_m. 0: whole along that axis.
  int first_view_row = 0, all_view_rows = 0;
  int first_pixel_row = 0, all_pixel_rows = 0;

  // Pupil position of view column c / view row r (the same bits in a tile as in the whole).
  double view_x(int c) const { return -eyebox_width_m / 2 + (c + 0.5) * eyebox_width_m / views_x; }
  double view_y(int r) const {
    return eyebox_height_m / 2 - (first_view_row + r + 0.5) * eyebox_height_m / whole_view_rows();
  }
  bool is_tile() const { return all_view_rows != 0 || all_pixel_rows != 0; }
  // View rows [first, first + count) of this light field (whole along the view rows).
  LightFieldGeometry ViewRows(int first, int count) const {
    LightFieldGeometry tile = *this;
    tile.first_view_row = first, tile.views_y = count, tile.all_view_rows = views_y;
    return tile;
  }
  // Pixel rows [first, first + count) of every view of this light field (whole along the pixel rows).
  LightFieldGeometry PixelRows(int first, int count) const {
    LightFieldGeometry tile = *this;
    tile.first_pixel_row = first, tile.rows = count, tile.all_pixel_rows = rows;
    return tile;
  }
  int whole_view_rows() const { return all_view_rows ? all_view_rows : views_y; }
  int whole_pixel_rows() const { return all_pixel_rows ? all_pixel_rows : rows; }
  // Origin-plane y of the point `position` pixel heights below the window's
  // top edge (pixel row i's center: first_pixel_row + i + 0.5).
  double window_y(double position) const { return window_top_m - position * window_height_m / whole_pixel_rows(); }
  // Origin-plane position of pixel column j / pixel row i.
  double pixel_x(int j) const { return window_left_m + (j + 0.5) * window_width_m / cols; }
  double pixel_y(int i) const { return window_y(first_pixel_row + i + 0.5); }

  // The same rays: every field equal (a tile equals only the same tile).
  bool operator==(const LightFieldGeometry&) const = default;

  size_t view_count() const { return static_cast<size_t>(views_x) * views_y; }
  size_t pixels_per_view() const { return static_cast<size_t>(cols) * rows; }
  size_t ray_count() const { return view_count() * pixels_per_view(); }
  // Index of view (row r, col c); views are stored row-major.
  size_t view_index(int r, int c) const { return static_cast<size_t>(r) * views_x + c; }
};

struct LightField {
  LightFieldGeometry geometry;
  // [view][row][col][channel], channels R, G, B.
  std::vector<float, HugePageAllocator<float>> rgb;
  // [view][row][col], eye-space z (m) of the first surface; empty when absent.
  std::vector<float> depth;
  std::string scene;  // free text from the manifest

  explicit LightField(const LightFieldGeometry& g = {}) : geometry(g), rgb(g.ray_count() * 3, 0.0f) {}

  float* view(size_t v) { return rgb.data() + v * geometry.pixels_per_view() * 3; }
  const float* view(size_t v) const { return rgb.data() + v * geometry.pixels_per_view() * 3; }
};

}  // namespace layerlab

// The pictures a report shows are written at the size it shows them (one
// image pixel to one CSS pixel): an image wider than the page's slot is
// reduced by the smallest whole factor that fits, each pixel the mean of a
// factor x factor block of the original (a partial block at the right or
// bottom edge: the mean of what it covers). The data files (EXR) keep every
// sample.
#pragma once

#include <cstdint>
#include <vector>

namespace layerlab {

// The widest PNG each kind of the report's figures shows one to one: a layer
// pattern, panel image or target view in a grid of several, and a retinal
// image beside natural viewing's (analysis/html_report.cpp lays them out).
inline constexpr int kPreviewWidthPx = 480, kRetinaWidthPx = 720;

// The smallest whole factor that brings `width` to at most `max_width` (1 when it fits).
int ShrinkFactor(int width, int max_width);

template <typename T>
struct ShownImage {
  int width = 0, height = 0, factor = 1;
  std::vector<T> pixels;  // [row][col][channel]
};

// Linear light: block means in double.
ShownImage<float> ShrinkToWidth(int width, int height, int channels, const std::vector<float>& pixels, int max_width);
// 8-bit codes (a panel's drive values): block means of the codes, rounded.
ShownImage<uint8_t> ShrinkToWidth(int width, int height, int channels, const std::vector<uint8_t>& pixels,
                                  int max_width);

}  // namespace layerlab

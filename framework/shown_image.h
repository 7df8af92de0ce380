// The pictures a report shows are written at the size it shows them (one
// image pixel to one CSS pixel): an image wider than the page's slot is
// reduced by the smallest whole factor that fits, each pixel the mean of a
// factor x factor block of the original (a partial block at the right or
// bottom edge: the mean of what it covers). The data files (EXR) keep every
// sample.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "layerlab/framework/png_writer.h"

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

// What a picture was written at: its size, the factor it was reduced by, and (sRGB) how many values lay
// above white and were clipped.
struct ShownPng {
  int width = 0, height = 0, factor = 1;
  size_t clipped = 0;
};

// Linear RGB as an sRGB PNG (WriteSrgbPng) reduced to `max_width`; written as it is, without a copy, when it fits.
ShownPng WriteShownSrgbPng(const std::string& path, int width, int height, const std::vector<float>& rgb, int max_width,
                           PngCompression compression = PngCompression::kSmallest);
// 8-bit RGB codes as a PNG (WritePng8) reduced to `max_width`, without a copy when it fits.
ShownPng WriteShownPng8(const std::string& path, int width, int height, const std::vector<uint8_t>& rgb, int max_width);

}  // namespace layerlab

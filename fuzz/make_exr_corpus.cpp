// Writes the EXR seed corpus (fuzz/corpus/exr/): tiny valid files in the
// shapes layerlab reads (RGB views, Z depth maps, half channels, a shifted
// data window, tiles), one with a negative value, and truncated copies.
// Usage: make_exr_corpus OUT_DIR  (run once; the files are committed).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfTileDescriptionAttribute.h>
#include <OpenEXR/ImfTiledOutputFile.h>

#include "layerlab/framework/exr_image.h"

namespace fs = std::filesystem;
using layerlab::Image;

namespace {

std::vector<char> ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void WriteAll(const fs::path& path, const std::vector<char>& bytes, size_t n) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(std::min(n, bytes.size())));
}

// Half RGB with the data window starting at (-1, -1), no compression.
void WriteShiftedHalf(const fs::path& path) {
  Imath::Box2i window({-1, -1}, {1, 0});
  Imf::Header header(window, window);
  header.compression() = Imf::NO_COMPRESSION;
  std::vector<half> pixels(3 * 2 * 3, half(0.5f));
  Imf::FrameBuffer frame;
  // The data window starts at (-1, -1): pixel (0, 0) lies 4 pixels into the buffer.
  char* base = reinterpret_cast<char*>(pixels.data()) + 4 * 3 * sizeof(half);
  for (int c = 0; c < 3; ++c) {
    const char* name = c == 0 ? "R" : c == 1 ? "G" : "B";
    header.channels().insert(name, Imf::Channel(Imf::HALF));
    frame.insert(name, Imf::Slice(Imf::HALF, base + c * sizeof(half), 3 * sizeof(half), 3 * 3 * sizeof(half)));
  }
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(2);
}

// Float RGB in 2 x 2 tiles, PIZ-compressed.
void WriteTiled(const fs::path& path) {
  const int w = 3, h = 3;
  Imf::Header header(w, h);
  header.compression() = Imf::PIZ_COMPRESSION;
  header.setTileDescription(Imf::TileDescription(2, 2, Imf::ONE_LEVEL));
  std::vector<float> pixels(w * h * 3, 0.25f);
  Imf::FrameBuffer frame;
  char* base = reinterpret_cast<char*>(pixels.data());
  for (int c = 0; c < 3; ++c) {
    const char* name = c == 0 ? "R" : c == 1 ? "G" : "B";
    header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    frame.insert(name, Imf::Slice(Imf::FLOAT, base + c * sizeof(float), 3 * sizeof(float), 3 * sizeof(float) * w));
  }
  Imf::TiledOutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
    return 2;
  }
  fs::path out(argv[1]);
  fs::create_directories(out);
  layerlab::WriteExr(
      (out / "rgb_2x2.exr").string(),
      Image{2, 2, {"R", "G", "B"}, {0, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.8f, 0.9f, 1.0f, 2.0f}});
  layerlab::WriteExr((out / "z_3x1.exr").string(), Image{3, 1, {"Z"}, {0.5f, 1.0f, 4.0f}});
  layerlab::WriteExr((out / "rgbz_1x1.exr").string(), Image{1, 1, {"R", "G", "B", "Z"}, {1, 1, 1, 2}});
  layerlab::WriteExr((out / "negative_1x1.exr").string(), Image{1, 1, {"R", "G", "B"}, {1, -1, 1}});
  WriteShiftedHalf(out / "half_shifted_3x2.exr");
  WriteTiled(out / "tiled_3x3.exr");
  // Truncated copies: inside the header, and inside the pixel data.
  std::vector<char> rgb = ReadAll(out / "rgb_2x2.exr");
  WriteAll(out / "rgb_2x2_truncated_header.exr", rgb, 40);
  WriteAll(out / "rgb_2x2_truncated_pixels.exr", rgb, rgb.size() - 8);
  std::vector<char> tiled = ReadAll(out / "tiled_3x3.exr");
  WriteAll(out / "tiled_3x3_truncated.exr", tiled, tiled.size() * 3 / 4);
  WriteAll(out / "magic_only.exr", {0x76, 0x2f, 0x31, 0x01}, 4);
  return 0;
}

#include "layerlab/framework/png_header.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "layerlab/framework/checked_count.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/file_kind.h"

namespace layerlab {
namespace {

uint32_t BigEndian32(const unsigned char* p) {
  return uint32_t{p[0]} << 24 | uint32_t{p[1]} << 16 | uint32_t{p[2]} << 8 | uint32_t{p[3]};
}

}  // namespace

PngHeader ReadPngHeader(const std::string& path) {
  RequireRegularFile(path, "PNG file");  // a FIFO would block the open below
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open it");
  // Signature (8 bytes), then the IHDR chunk: length 13, "IHDR", width, height, depth, color type, ...
  std::array<unsigned char, 8 + 8 + 13> bytes{};
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  static constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (in.gcount() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0)
    throw Error(path + ": not a PNG file (no PNG signature)");
  if (in.gcount() < static_cast<std::streamsize>(bytes.size()))
    throw Error(path + ": truncated PNG file: it ends inside its header");
  if (BigEndian32(&bytes[8]) != 13 || std::memcmp(&bytes[12], "IHDR", 4) != 0)
    throw Error(path + ": corrupt PNG file: its first chunk is not a 13-byte IHDR header");
  PngHeader header;
  header.width = BigEndian32(&bytes[16]);
  header.height = BigEndian32(&bytes[20]);
  header.bit_depth = bytes[24];
  const int color_type = bytes[25];
  switch (color_type) {
    case 0:
      header.channels = 1;
      break;
    case 2:
      header.channels = 3;
      break;
    case 3:
      header.channels = 3;
      break;  // palette entries are RGB
    case 4:
      header.channels = 2;
      break;
    case 6:
      header.channels = 4;
      break;
    default:
      throw Error(path + ": corrupt PNG file: unknown color type " + std::to_string(color_type));
  }
  if (header.width == 0 || header.height == 0)
    throw Error(path + ": corrupt PNG file: it declares " + std::to_string(header.width) + " x " +
                std::to_string(header.height) + " pixels");
  if (header.bit_depth != 1 && header.bit_depth != 2 && header.bit_depth != 4 && header.bit_depth != 8 &&
      header.bit_depth != 16)
    throw Error(path + ": corrupt PNG file: " + std::to_string(header.bit_depth) + " bits per sample");
  return header;
}

void RequirePngWithinLimit(const std::string& path, const PngHeader& header, size_t max_pixels) {
  const size_t pixels = CheckedProduct({header.width, header.height}, path + ": the PNG's pixels");
  CheckedProduct({pixels, static_cast<size_t>(header.channels)}, path + ": the PNG's samples");
  if (pixels > max_pixels)
    throw Error(path + ": the PNG declares " + std::to_string(header.width) + " x " + std::to_string(header.height) +
                " pixels; the limit is " + std::to_string(max_pixels) + " pixels (it is not decoded)");
}

}  // namespace layerlab

#include "framework/exr_image.h"

#include <cmath>
#include <cstring>
#include <fstream>

#include <OpenEXR/IexBaseExc.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include "framework/atomic_file.h"
#include "framework/error.h"

namespace layerlab {
namespace {

constexpr int kMaxSide = 1 << 15;

// OpenEXR allocates whatever a header declares; bound it before any read.
void LimitHeaderSizes() {
  static const bool once = [] {
    Imf::Header::setMaxImageSize(kMaxSide, kMaxSide);
    Imf::Header::setMaxTileSize(kMaxSide, kMaxSide);
    return true;
  }();
  (void)once;
}

void RequireExrMagic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open for reading: " + std::strerror(errno));
  unsigned char magic[4] = {0, 0, 0, 0};
  in.read(reinterpret_cast<char*>(magic), 4);
  if (in.gcount() != 4 || magic[0] != 0x76 || magic[1] != 0x2f || magic[2] != 0x31 || magic[3] != 0x01)
    throw Error(path + ": not an OpenEXR file");
}

}  // namespace

ExrSize ReadExrSize(const std::string& path) {
  LimitHeaderSizes();
  RequireExrMagic(path);
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i& dw = file.header().dataWindow();
    return {dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1};
  } catch (const std::exception& e) {
    throw Error(path + ": unreadable OpenEXR header: " + e.what());
  }
}

Image ReadExr(const std::string& path, const std::vector<std::string>& channels, const ExrLimits& limits) {
  LimitHeaderSizes();
  RequireExrMagic(path);
  Image image;
  image.channels = channels;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i& dw = file.header().dataWindow();
    long long width = static_cast<long long>(dw.max.x) - dw.min.x + 1;
    long long height = static_cast<long long>(dw.max.y) - dw.min.y + 1;
    if (width <= 0 || height <= 0 || width * height > limits.max_pixels)
      throw Error(path + ": declares " + std::to_string(width) + " x " + std::to_string(height) +
                  " pixels; the limit is " + std::to_string(limits.max_pixels));
    const Imf::ChannelList& available = file.header().channels();
    for (const std::string& name : channels)
      if (!available.findChannel(name.c_str())) {
        std::string present;
        for (auto it = available.begin(); it != available.end(); ++it) present += std::string(present.empty() ? "" : ", ") + it.name();
        throw Error(path + ": has no channel " + name + " (it has " + (present.empty() ? "none" : present) + ")");
      }
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    size_t n = channels.size();
    image.pixels.assign(static_cast<size_t>(width * height) * n, 0.0f);
    Imf::FrameBuffer frame;
    // The data window may not start at (0, 0): offset the base pointer.
    char* base = reinterpret_cast<char*>(image.pixels.data()) -
                 (static_cast<ptrdiff_t>(dw.min.y) * width + dw.min.x) * static_cast<ptrdiff_t>(n * sizeof(float));
    for (size_t c = 0; c < n; ++c)
      frame.insert(channels[c].c_str(), Imf::Slice(Imf::FLOAT, base + c * sizeof(float), n * sizeof(float),
                                                   n * sizeof(float) * width));
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(path + ": corrupt or truncated OpenEXR file: " + e.what());
  }
  for (size_t k = 0; k < image.pixels.size(); ++k) {
    float v = image.pixels[k];
    if (std::isfinite(v) && v >= 0) continue;
    size_t pixel = k / channels.size();
    throw Error(path + ": pixel (row " + std::to_string(pixel / image.width) + ", col " +
                std::to_string(pixel % image.width) + ") channel " + channels[k % channels.size()] + " is " +
                (std::isnan(v) ? "NaN" : std::isinf(v) ? (v > 0 ? "+inf" : "-inf") : "negative (" + std::to_string(v) + ")") +
                "; light must be finite and non-negative");
  }
  return image;
}

void WriteExr(const std::string& path, const Image& image) {
  size_t n = image.channels.size();
  if (image.width <= 0 || image.height <= 0 || n == 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * image.height * n)
    throw Error(path + ": internal error: image buffer does not match its size");
  AtomicFile out(path);
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frame;
    char* base = const_cast<char*>(reinterpret_cast<const char*>(image.pixels.data()));
    for (size_t c = 0; c < n; ++c) {
      header.channels().insert(image.channels[c].c_str(), Imf::Channel(Imf::FLOAT));
      frame.insert(image.channels[c].c_str(),
                   Imf::Slice(Imf::FLOAT, base + c * sizeof(float), n * sizeof(float), n * sizeof(float) * image.width));
    }
    Imf::OutputFile file(out.temp_path().c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    throw Error(path + ": cannot write OpenEXR file: " + e.what());
  }
  out.Commit();
}

}  // namespace layerlab

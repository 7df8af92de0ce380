#include "layerlab/framework/exr_image.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>

#include <Imath/half.h>
#include <OpenEXR/IexBaseExc.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/openexr.h>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/file_kind.h"
#include "layerlab/framework/units.h"

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

// The attribute types OpenEXR's C++ reader reads at their own size, whatever the declared one.
const std::map<std::string, int>& FixedAttributeSizes() {
  static const std::map<std::string, int> kFixedSizes = {{"box2i", 16},
                                                         {"box2f", 16},
                                                         {"chromaticities", 32},
                                                         {"compression", 1},
                                                         {"deepImageState", 1},
                                                         {"double", 8},
                                                         {"envmap", 1},
                                                         {"float", 4},
                                                         {"int", 4},
                                                         {"keycode", 28},
                                                         {"lineOrder", 1},
                                                         {"m33f", 36},
                                                         {"m33d", 72},
                                                         {"m44f", 64},
                                                         {"m44d", 128},
                                                         {"rational", 8},
                                                         {"tiledesc", 9},
                                                         {"timecode", 8},
                                                         {"v2i", 8},
                                                         {"v2f", 8},
                                                         {"v2d", 16},
                                                         {"v3i", 12},
                                                         {"v3f", 12},
                                                         {"v3d", 24}};
  return kFixedSizes;
}

// Reads an EXR file's headers field by field, each read checked against the file's end.
class ExrHeaderReader {
 public:
  ExrHeaderReader(const std::string& path, std::ifstream& in, long long file_size, size_t max_name)
      : path_(path), in_(in), file_size_(file_size), max_name_(max_name) {}

  Error Corrupt(const std::string& why) const { return Error(path_ + ": corrupt or truncated OpenEXR file: " + why); }
  long long Remaining() const { return file_size_ - static_cast<long long>(in_.tellg()); }

  void ReadName(std::string& out) {
    out.clear();
    for (char c; in_.get(c);) {
      if (c == '\0') return;
      if (out.size() == max_name_) throw Corrupt("a header name longer than " + std::to_string(max_name_) + " bytes");
      out += c;
    }
    throw Corrupt("the header ends inside a name");
  }

  uint32_t ReadU32() {
    unsigned char b[4];
    in_.read(reinterpret_cast<char*>(b), 4);
    if (in_.gcount() != 4) throw Corrupt("the header ends early");
    return static_cast<uint32_t>(b[0]) | static_cast<uint32_t>(b[1]) << 8 | static_cast<uint32_t>(b[2]) << 16 |
           static_cast<uint32_t>(b[3]) << 24;
  }

  // Past an attribute's value: fixed-size types at their own size, channel
  // lists and previews by their content, everything else at the declared size.
  void SkipValue(const std::string& name, const std::string& type, int32_t size) {
    if (auto fixed = FixedAttributeSizes().find(type); fixed != FixedAttributeSizes().end()) {
      in_.seekg(fixed->second, std::ios::cur);
    } else if (type == "chlist") {
      std::string channel;
      for (ReadName(channel); !channel.empty(); ReadName(channel)) in_.seekg(16, std::ios::cur);
    } else if (type == "preview") {
      // Two 32-bit sides: their product can pass 2^63, so divide instead.
      const uint64_t width = ReadU32(), height = ReadU32();
      const uint64_t left = static_cast<uint64_t>(std::max(Remaining(), 0LL));
      if (width != 0 && height > left / 4 / width) throw Corrupt("the preview image runs past the end of the file");
      in_.seekg(static_cast<std::streamoff>(width * height * 4), std::ios::cur);
    } else {
      if (size > Remaining())
        throw Corrupt("attribute \"" + name + "\" declares " + std::to_string(size) + " bytes; the file has " +
                      std::to_string(Remaining()) + " left");
      in_.seekg(size, std::ios::cur);
    }
    if (!in_ || Remaining() < 0) throw Corrupt("the header ends inside attribute \"" + name + "\"");
  }

 private:
  const std::string& path_;
  std::ifstream& in_;
  const long long file_size_;
  const size_t max_name_;
};

// Walks the headers the way OpenEXR's C++ reader does (Header::readFrom): known
// fixed-size types are read at their own size whatever the declared one,
// channel lists and previews by their content, everything else at the declared
// size. Each read that allocates must fit in what is left of the file. The C
// core's parse (below) alone does not suffice: it trusts declared sizes where
// the C++ reader does not, and the two can part ways on a corrupt file.
void RequireCppHeaderWithinFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw Error(path + ": cannot open for reading: " + std::strerror(errno));
  const long long file_size = static_cast<long long>(in.tellg());
  in.seekg(0);
  unsigned char start[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  in.read(reinterpret_cast<char*>(start), 8);
  const bool multipart = start[5] & 0x10, long_names = start[5] & 0x04;  // version flags, bits 12 and 10
  ExrHeaderReader reader(path, in, file_size, long_names ? 255 : 31);
  if (in.gcount() != 8) throw reader.Corrupt("no version field");
  for (bool more = true; more;) {
    int attributes = 0;
    for (std::string name, type;; ++attributes) {
      reader.ReadName(name);
      if (name.empty()) break;
      reader.ReadName(type);
      const int32_t size = static_cast<int32_t>(reader.ReadU32());
      if (size < 0) throw reader.Corrupt("attribute \"" + name + "\" has a negative size");
      reader.SkipValue(name, type, size);
    }
    more = multipart && attributes > 0;
  }
}

// OpenEXR's C++ reader allocates each header attribute at its declared size
// before reading it: a few hundred bytes could make it allocate and clear
// gigabytes. OpenEXR's C core parses headers with sizes checked against the
// file, so it reads the headers first; the C++ reader runs only on what it accepts.
void RequireSaneExrHeaders(const std::string& path) {
  RequireRegularFile(path, "EXR file");  // a FIFO would block the open below
  RequireExrMagic(path);
  RequireCppHeaderWithinFile(path);
  thread_local std::string message;
  message.clear();
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = [](exr_const_context_t, exr_result_t, const char* text) {
    if (message.empty() && text) message = text;
  };
  init.max_image_width = init.max_image_height = kMaxSide;
  init.max_tile_width = init.max_tile_height = kMaxSide;
  exr_context_t context = nullptr;
  exr_result_t result = exr_start_read(&context, path.c_str(), &init);
  exr_finish(&context);
  if (result != EXR_ERR_SUCCESS)
    throw Error(path + ": corrupt or truncated OpenEXR file: " +
                (message.empty() ? std::string(exr_get_default_error_message(result)) : message));
}

}  // namespace

ExrSize ReadExrSize(const std::string& path) {
  LimitHeaderSizes();
  RequireSaneExrHeaders(path);
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i& dw = file.header().dataWindow();
    return {dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1};
  } catch (const std::exception& e) {
    throw Error(path + ": unreadable OpenEXR header: " + e.what());
  }
}

std::vector<std::string> ReadExrChannelNames(const std::string& path) {
  LimitHeaderSizes();
  RequireSaneExrHeaders(path);
  try {
    Imf::InputFile file(path.c_str());
    std::vector<std::string> names;
    const Imf::ChannelList& channels = file.header().channels();
    for (auto it = channels.begin(); it != channels.end(); ++it) names.push_back(it.name());
    return names;
  } catch (const std::exception& e) {
    throw Error(path + ": unreadable OpenEXR header: " + e.what());
  }
}

Image ReadExr(const std::string& path, const std::vector<std::string>& channels, const ExrLimits& limits) {
  LimitHeaderSizes();
  RequireSaneExrHeaders(path);
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
        for (auto it = available.begin(); it != available.end(); ++it)
          present += std::string(present.empty() ? "" : ", ") + it.name();
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
      frame.insert(channels[c].c_str(),
                   Imf::Slice(Imf::FLOAT, base + c * sizeof(float), n * sizeof(float), n * sizeof(float) * width));
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(path + ": corrupt or truncated OpenEXR file: " + e.what());
  }
  if (const std::string why = FindValueThatIsNotLight(image.pixels.data(), image.pixels.size(), image.width, channels);
      !why.empty())
    throw Error(path + ": " + why);
  return image;
}

std::string FindValueThatIsNotLight(const float* values, size_t count, int width,
                                    const std::vector<std::string>& channels) {
  for (size_t k = 0; k < count; ++k) {
    const float v = values[k];
    if (std::isfinite(v) && v >= 0) continue;
    const size_t pixel = k / channels.size();
    return "pixel (row " + std::to_string(pixel / width) + ", col " + std::to_string(pixel % width) + ") channel " +
           channels[k % channels.size()] + " is " +
           (std::isnan(v)   ? "NaN"
            : std::isinf(v) ? (v > 0 ? "+inf" : "-inf")
                            : "negative (" + std::to_string(v) + ")") +
           "; light must be finite and non-negative";
  }
  return "";
}

void WriteExr(const std::string& path, const Image& image, ExrCompression compression, ExrPixels pixels) {
  size_t n = image.channels.size();
  if (image.width <= 0 || image.height <= 0 || n == 0 ||
      image.pixels.size() != static_cast<size_t>(image.width) * image.height * n)
    throw Error(path + ": internal error: image buffer does not match its size");
  AtomicFile out(path);
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = compression == ExrCompression::kZip ? Imf::ZIP_COMPRESSION : Imf::NO_COMPRESSION;
    Imf::FrameBuffer frame;
    std::vector<Imath::half> halves;
    char* base = const_cast<char*>(reinterpret_cast<const char*>(image.pixels.data()));
    Imf::PixelType type = Imf::FLOAT;
    size_t size = sizeof(float);
    if (pixels == ExrPixels::kHalf) {
      halves.resize(image.pixels.size());
      for (size_t k = 0; k < halves.size(); ++k) {
        if (!(std::abs(image.pixels[k]) <= HALF_MAX))
          throw Error(path + ": " + FormatGeneral(image.pixels[k]) +
                      " does not fit a half-float EXR (at most 65504); write it as float");
        halves[k] = Imath::half(image.pixels[k]);
      }
      base = reinterpret_cast<char*>(halves.data()), type = Imf::HALF, size = sizeof(Imath::half);
    }
    for (size_t c = 0; c < n; ++c) {
      header.channels().insert(image.channels[c].c_str(), Imf::Channel(type));
      frame.insert(image.channels[c].c_str(), Imf::Slice(type, base + c * size, n * size, n * size * image.width));
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

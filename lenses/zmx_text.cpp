#include "layerlab/lenses/zmx_text.h"

#include <cstdint>

#include "layerlab/framework/error.h"

namespace layerlab::lenses::zmx {
namespace {

bool StartsWith(const std::string& bytes, std::initializer_list<unsigned char> prefix) {
  if (bytes.size() < prefix.size()) return false;
  size_t i = 0;
  for (unsigned char b : prefix) {
    if (static_cast<unsigned char>(bytes[i++]) != b) return false;
  }
  return true;
}

void AppendUtf8(uint32_t code_point, std::string* out) {
  if (code_point < 0x80) {
    *out += static_cast<char>(code_point);
  } else if (code_point < 0x800) {
    *out += static_cast<char>(0xC0 | (code_point >> 6));
    *out += static_cast<char>(0x80 | (code_point & 0x3F));
  } else if (code_point < 0x10000) {
    *out += static_cast<char>(0xE0 | (code_point >> 12));
    *out += static_cast<char>(0x80 | ((code_point >> 6) & 0x3F));
    *out += static_cast<char>(0x80 | (code_point & 0x3F));
  } else {
    *out += static_cast<char>(0xF0 | (code_point >> 18));
    *out += static_cast<char>(0x80 | ((code_point >> 12) & 0x3F));
    *out += static_cast<char>(0x80 | ((code_point >> 6) & 0x3F));
    *out += static_cast<char>(0x80 | (code_point & 0x3F));
  }
}

std::string Utf16LeToUtf8(const std::string& bytes, const std::string& source) {
  if (bytes.size() % 2 != 0) {
    throw Error(source + ": UTF-16LE text of an odd number of bytes (" + std::to_string(bytes.size()) + ")");
  }
  std::string out;
  out.reserve(bytes.size() / 2);
  int line = 1;
  auto unit = [&](size_t i) {
    return static_cast<uint32_t>(static_cast<unsigned char>(bytes[i]) | static_cast<unsigned char>(bytes[i + 1]) << 8);
  };
  for (size_t i = 2; i < bytes.size(); i += 2) {
    uint32_t c = unit(i);
    if (c >= 0xD800 && c < 0xDC00 && i + 3 < bytes.size() && unit(i + 2) >= 0xDC00 && unit(i + 2) < 0xE000) {
      c = 0x10000 + ((c - 0xD800) << 10) + (unit(i + 2) - 0xDC00);
      i += 2;
    } else if (c >= 0xD800 && c < 0xE000) {
      throw Error(source + ":" + std::to_string(line) + ": invalid UTF-16LE (an unpaired surrogate)");
    }
    if (c == 0) throw Error(source + ":" + std::to_string(line) + ": a NUL character");
    if (c == '\n') ++line;
    AppendUtf8(c, &out);
  }
  return out;
}

}  // namespace

std::string DecodeText(const std::string& bytes, const std::string& source_name) {
  if (StartsWith(bytes, {0xFF, 0xFE, 0x00, 0x00}) || StartsWith(bytes, {0x00, 0x00, 0xFE, 0xFF})) {
    throw Error(source_name + ": UTF-32 text is not supported (save the .zmx as UTF-8 or UTF-16LE)");
  }
  if (StartsWith(bytes, {0xFE, 0xFF})) {
    throw Error(source_name + ": UTF-16BE text is not supported (save the .zmx as UTF-8 or UTF-16LE)");
  }
  if (StartsWith(bytes, {0xFF, 0xFE})) return Utf16LeToUtf8(bytes, source_name);
  const size_t start = StartsWith(bytes, {0xEF, 0xBB, 0xBF}) ? 3 : 0;
  int line = 1;
  for (size_t i = start; i < bytes.size(); ++i) {
    if (bytes[i] == '\n') ++line;
    if (bytes[i] == '\0') {
      throw Error(source_name + ":" + std::to_string(line) +
                  ": a NUL byte (UTF-16 without its byte-order mark? .zmx files are read as UTF-8, or as "
                  "UTF-16LE with its BOM)");
    }
  }
  return bytes.substr(start);
}

}  // namespace layerlab::lenses::zmx

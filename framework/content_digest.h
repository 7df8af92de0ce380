// A 64-bit content digest (FNV-1a), to tell whether two inputs are the same
// (a checkpoint's target against the one a resume reads). Not cryptographic.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace layerlab {

class ContentDigest {
 public:
  ContentDigest& add(const void* data, size_t bytes);
  ContentDigest& add(const std::string& text) { return add(text.data(), text.size()); }
  uint64_t value() const { return state_; }
  std::string hex() const;  // 16 lowercase hex digits

 private:
  uint64_t state_ = 14695981039346656037ull;
};

}  // namespace layerlab

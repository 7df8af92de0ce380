#include "layerlab/framework/content_digest.h"

#include <cstdio>

namespace layerlab {

ContentDigest& ContentDigest::add(const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  uint64_t h = state_;
  for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  state_ = h;
  return *this;
}

std::string ContentDigest::hex() const {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(state_));
  return text;
}

}  // namespace layerlab

// EXR reading: the input is written to a scratch file and read the ways
// layerlab reads views and depth maps (R, G, B; Z) and sizes them. OpenEXR's
// own exceptions must come out as layerlab::Error.
#include <cstddef>
#include <cstdint>

#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = (layerlab::fuzz::ScratchDir() / "input.exr").string();
  layerlab::fuzz::WriteBytes(path, data, size);
  // A smaller pixel budget than the default 64 Mpixel keeps each run fast;
  // the checks in front of the allocation are the same.
  layerlab::ExrLimits limits;
  limits.max_pixels = 1 << 20;
  try {
    (void)layerlab::ReadExrSize(path);
  } catch (const layerlab::Error&) {
  }
  try {
    (void)layerlab::ReadExr(path, {"R", "G", "B"}, limits);
  } catch (const layerlab::Error&) {
  }
  try {
    (void)layerlab::ReadExr(path, {"Z"}, limits);
  } catch (const layerlab::Error&) {
  }
  return 0;
}

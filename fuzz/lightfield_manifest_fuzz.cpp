// The light-field manifest: the input is written as lightfield.json into a
// per-process scratch folder, then read and validated by ReadLightFieldGeometry.
#include <cstddef>
#include <cstdint>

#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto& folder = layerlab::fuzz::ScratchDir();
  layerlab::fuzz::WriteBytes(folder / "lightfield.json", data, size);
  try {
    (void)layerlab::ReadLightFieldGeometry(folder.string());
  } catch (const layerlab::Error&) {
  }
  return 0;
}

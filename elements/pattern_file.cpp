#include "layerlab/elements/pattern_file.h"

#include <algorithm>
#include <filesystem>

#include "layerlab/framework/exr_image.h"

namespace layerlab {

PatternFile ReadPatternFile(Params& p, const std::string& key, const std::string& what) {
  PatternFile out;
  out.name = p.string(key);
  out.path = (std::filesystem::path(p.where().file).parent_path() / out.name).string();
  const std::string& path = out.path;
  Image image;
  try {
    const std::vector<std::string> names = ReadExrChannelNames(path);
    const bool rgb = std::count(names.begin(), names.end(), "R") && std::count(names.begin(), names.end(), "G") &&
                     std::count(names.begin(), names.end(), "B");
    if (!rgb && !std::count(names.begin(), names.end(), "Y"))
      throw Error(path + ": has neither channels R, G, B nor Y");
    image = ReadExr(path, rgb ? std::vector<std::string>{"R", "G", "B"} : std::vector<std::string>{"Y"});
  } catch (const Error& e) {
    p.fail(key, e.what());
  }
  auto pattern = std::make_shared<std::vector<float>>(static_cast<size_t>(image.width) * image.height * 3);
  const size_t channels = image.channels.size();
  for (size_t i = 0; i < static_cast<size_t>(image.width) * image.height; ++i)
    for (size_t c = 0; c < 3; ++c) {
      const float v = image.pixels[i * channels + (channels == 3 ? c : 0)];
      if (!(v >= 0.0f && v <= 1.0f))
        p.fail(key, path + ": pixel (row " + std::to_string(i / image.width) + ", col " +
                        std::to_string(i % image.width) + ") holds " + std::to_string(v) + ", outside the " + what +
                        " range [0, 1]");
      (*pattern)[i * 3 + c] = v;
    }
  out.cols = image.width;
  out.rows = image.height;
  out.rgb = std::move(pattern);
  return out;
}

}  // namespace layerlab

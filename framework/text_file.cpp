#include "layerlab/framework/text_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "layerlab/framework/error.h"
#include "layerlab/framework/file_kind.h"
#include "layerlab/framework/file_read_observer.h"

namespace layerlab {

std::string ReadFileText(const std::string& path, size_t max_bytes) {
  std::error_code ec;
  auto size = std::filesystem::file_size(path, ec);
  if (ec) {
    const std::string why = ec.message();
    std::error_code link_ec;  // something is there: a FIFO, a folder, a link loop is named as such
    if (std::filesystem::exists(std::filesystem::symlink_status(path, link_ec))) RequireRegularFile(path);
    throw Error(path + ": cannot read: " + why);
  }
  if (size > max_bytes)
    throw Error({path, ""}, "file is " + std::to_string(size) + " bytes; the limit is " + std::to_string(max_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open for reading");
  AnnounceFileRead(path);
  std::ostringstream read;
  read << in.rdbuf();
  return read.str();
}

}  // namespace layerlab

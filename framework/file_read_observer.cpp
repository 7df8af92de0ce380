#include "layerlab/framework/file_read_observer.h"

#include <utility>

namespace layerlab {
namespace {

std::function<void(const std::string&)> observer;

}  // namespace

void AnnounceFileRead(const std::string& path) {
  if (observer) observer(path);
}

void OnFileReadForTesting(std::function<void(const std::string&)> read) { observer = std::move(read); }

}  // namespace layerlab

// A whole file's bytes, read the way every layerlab input is: a regular file
// (framework/file_kind.h), at most `max_bytes`, announced to the read
// observer (framework/file_read_observer.h). Throws layerlab::Error naming the
// path: "x.zmx: cannot read: No such file or directory", "x.zmx: /: file is
// 2000000 bytes; the limit is 1048576".
#pragma once

#include <cstddef>
#include <string>

namespace layerlab {

std::string ReadFileText(const std::string& path, size_t max_bytes);

}  // namespace layerlab

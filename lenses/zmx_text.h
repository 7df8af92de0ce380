// The characters of a .zmx file: UTF-8 (with or without its BOM) as it is,
// UTF-16LE with its BOM (OpticStudio's own) decoded to UTF-8. Refuses, naming
// `source_name`, UTF-16BE and UTF-32 (by their BOMs), NUL characters (BOM-less
// UTF-16 shows as NUL bytes) and broken UTF-16 (an odd byte count, an unpaired
// surrogate). Other bytes pass through: the reader needs only ASCII keywords
// and numbers, and refuses a line it cannot parse.
#pragma once

#include <string>

namespace layerlab::lenses::zmx {

std::string DecodeText(const std::string& bytes, const std::string& source_name);

}  // namespace layerlab::lenses::zmx

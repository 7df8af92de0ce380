// Strict JSON input: malformed text is reported with line and column,
// duplicate keys are refused (nlohmann would keep the last one silently),
// and size and nesting are bounded before anything recurses.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

namespace layerlab {

struct JsonLimits {
  size_t max_bytes = 16u << 20;  // scene and measurement files are small
  int max_depth = 64;
};

// `file` names the source in messages; the text is parsed as is.
nlohmann::json ParseJson(const std::string& text, const std::string& file, const JsonLimits& limits = {});

// What a read took from a file: its size and the digest of its bytes
// (framework/content_digest.h), so that a cache keys on exactly the bytes that
// were parsed without reading the file again.
struct FileBytes {
  uint64_t size = 0;
  uint64_t digest = 0;
};

// Reads and parses a file; refuses a missing, unreadable or oversized file.
// `bytes`, when given, receives what was read. Each read is announced
// (framework/file_read_observer.h).
nlohmann::json ReadJsonFile(const std::string& path, const JsonLimits& limits = {}, FileBytes* bytes = nullptr);

// "object", "array", "string", "number", "boolean", "null" for messages.
std::string JsonKindName(const nlohmann::json& value);

}  // namespace layerlab

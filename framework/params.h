// Typed, unit-aware access to one JSON object, remembering which keys were
// read (as Mitsuba's Properties and pbrt's ParameterDictionary do): after an
// element is built, any key it did not read is an error that suggests the
// closest known key, so "focal_lenght" is caught instead of defaulted.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"

namespace layerlab {

using Rgb = std::array<double, 3>;

// While one lives, every key that any Params on this thread is asked for
// (read, defaulted or tested with has()) is recorded under the JSON pointer of
// its object: the scene reference's test compares them with the key tables
// of the element files and section readers (docs/scene-reference.md).
class ParamsKeyRecorder {
 public:
  ParamsKeyRecorder();
  ~ParamsKeyRecorder();
  ParamsKeyRecorder(const ParamsKeyRecorder&) = delete;
  ParamsKeyRecorder& operator=(const ParamsKeyRecorder&) = delete;
  // JSON pointer of an object -> the keys asked of it.
  const std::map<std::string, std::set<std::string>>& keys() const { return keys_; }

 private:
  friend class Params;
  std::map<std::string, std::set<std::string>> keys_;
  ParamsKeyRecorder* previous_;
};

class Params {
 public:
  // Reads `object`, which must outlive this Params.
  Params(const nlohmann::json& object, Location where);
  // Reads a value it owns (for small objects assembled on the fly).
  Params(nlohmann::json&& object, Location where);

  const Location& where() const { return where_; }
  Location where(const std::string& key) const { return where_.child(key); }
  bool has(const std::string& key) const;

  // Quantities: a JSON number is SI; a string carries its unit.
  double quantity(const std::string& key, Dimension d);
  double quantity(const std::string& key, Dimension d, double fallback);
  std::optional<double> optional_quantity(const std::string& key, Dimension d);
  // A depth given as "0.4 D" or "2.5 m"; a bare number is ambiguous and refused.
  std::optional<Depth> optional_depth(const std::string& key);

  // Integers refuse fractions, strings, and values outside [min, max]:
  // nothing is truncated or wrapped.
  int64_t integer(const std::string& key, int64_t min, int64_t max);
  int64_t integer(const std::string& key, int64_t min, int64_t max, int64_t fallback);

  bool boolean(const std::string& key, bool fallback);
  std::string string(const std::string& key);
  std::string string(const std::string& key, const std::string& fallback);
  // One of `allowed`, or an error listing them.
  std::string choice(const std::string& key, const std::vector<std::string>& allowed, const std::string& fallback);

  // A fraction in [0, 1]: a number, "30 %", or an [r, g, b] array of those.
  Rgb fraction_rgb(const std::string& key, double fallback);
  Rgb fraction_rgb(const std::string& key);

  // A pair of quantities, [x, y], or one quantity used for both.
  std::array<double, 2> quantity_pair(const std::string& key, Dimension d, std::array<double, 2> fallback);
  std::array<int64_t, 2> integer_pair(const std::string& key, int64_t min, int64_t max);

  // The raw value (marks it read), for element-specific structures.
  const nlohmann::json& raw(const std::string& key);
  // A nested object as its own Params, sharing the "read" bookkeeping rule:
  // call check_all_read() on it too.
  Params object(const std::string& key);

  // Refuses a value that is present but outside (lo, hi) or [lo, hi].
  void require_range(const std::string& key, double value, double lo, double hi, bool lo_open, bool hi_open) const;

  // Throws for the first key that was never read, suggesting the closest read one.
  void check_all_read() const;
  // Marks a key as known (consumed by someone else, e.g. the scene walker).
  void mark_read(const std::string& key);

  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

 private:
  const nlohmann::json& at(const std::string& key);
  double quantity_value(const nlohmann::json& v, const Location& at, Dimension d) const;
  double fraction_value(const nlohmann::json& v, const Location& at) const;
  void record(const std::string& key) const;  // for a live ParamsKeyRecorder

  std::shared_ptr<const nlohmann::json> owned_;  // set when this Params owns its object
  const nlohmann::json* object_;
  Location where_;
  std::set<std::string> read_;
};

// Edit distance, for "did you mean" suggestions.
size_t EditDistance(const std::string& a, const std::string& b);
// The candidate closest to `word`, if it is close enough to be a likely typo.
std::optional<std::string> ClosestWord(const std::string& word, const std::vector<std::string>& candidates);
// "a, b or c".
std::string JoinWords(const std::vector<std::string>& words, const std::string& last_sep = " or ");

}  // namespace layerlab

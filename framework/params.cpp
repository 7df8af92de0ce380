#include "layerlab/framework/params.h"

#include <algorithm>
#include <cmath>

#include "layerlab/framework/json_file.h"

namespace layerlab {

using nlohmann::json;

Params::Params(const json& object, Location where) : object_(&object), where_(std::move(where)) {
  if (!object_->is_object()) throw Error(where_, "expected an object, got " + JsonKindName(*object_));
}

Params::Params(json&& object, Location where)
    : owned_(std::make_shared<const json>(std::move(object))), object_(owned_.get()), where_(std::move(where)) {
  if (!object_->is_object()) throw Error(where_, "expected an object, got " + JsonKindName(*object_));
}

namespace {
thread_local ParamsKeyRecorder* active_recorder = nullptr;
}  // namespace

ParamsKeyRecorder::ParamsKeyRecorder() : previous_(active_recorder) { active_recorder = this; }
ParamsKeyRecorder::~ParamsKeyRecorder() { active_recorder = previous_; }

void Params::record(const std::string& key) const {
  if (active_recorder) active_recorder->keys_[where_.pointer].insert(key);
}

bool Params::has(const std::string& key) const {
  record(key);
  return object_->contains(key);
}

void Params::mark_read(const std::string& key) {
  record(key);
  read_.insert(key);
}

const json& Params::at(const std::string& key) {
  mark_read(key);
  auto it = object_->find(key);
  if (it == object_->end()) {
    // A key not read yet that is a near miss is the likelier mistake: a typo, named where it is.
    std::vector<std::string> unread;
    for (auto k = object_->begin(); k != object_->end(); ++k)
      if (!read_.count(k.key())) unread.push_back(k.key());
    if (auto near = ClosestWord(key, unread))
      throw Error(where_.child(*near), "unknown key \"" + *near + "\"; did you mean \"" + key + "\"?");
    fail(key, "missing required key \"" + key + "\"");
  }
  return *it;
}

const json& Params::raw(const std::string& key) { return at(key); }

void Params::fail(const std::string& key, const std::string& message) const { throw Error(where_.child(key), message); }

double Params::quantity_value(const json& v, const Location& loc, Dimension d) const {
  if (v.is_number()) {
    double x = v.get<double>();
    if (!std::isfinite(x)) throw Error(loc, "expected " + DimensionName(d) + ", got a non-finite number");
    return x;
  }
  if (!v.is_string())
    throw Error(loc, "expected " + DimensionName(d) + " (a number in SI units or a string such as \"" +
                         (d == Dimension::kLength  ? "75 mm"
                          : d == Dimension::kAngle ? "36 deg"
                                                   : "1") +
                         "\"), got " + JsonKindName(v));
  try {
    return ParseQuantity(v.get<std::string>(), d);
  } catch (const Error& e) {
    throw Error(loc, e.message());
  }
}

double Params::quantity(const std::string& key, Dimension d) { return quantity_value(at(key), where_.child(key), d); }

double Params::quantity(const std::string& key, Dimension d, double fallback) {
  return optional_quantity(key, d).value_or(fallback);
}

std::optional<double> Params::optional_quantity(const std::string& key, Dimension d) {
  mark_read(key);
  if (!has(key)) return std::nullopt;
  return quantity(key, d);
}

std::optional<Depth> Params::optional_depth(const std::string& key) {
  mark_read(key);
  if (!has(key)) return std::nullopt;
  const json& v = at(key);
  if (!v.is_string())
    fail(key, "expected a depth with its unit, such as \"0.4 D\" or \"2.5 m\", got " + JsonKindName(v));
  try {
    return ParseDepth(v.get<std::string>());
  } catch (const Error& e) {
    fail(key, e.message());
  }
}

int64_t Params::integer(const std::string& key, int64_t min, int64_t max) {
  const json& v = at(key);
  std::string range = "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (v.is_number_unsigned()) {
    uint64_t u = v.get<uint64_t>();
    if (max >= 0 && u <= static_cast<uint64_t>(max) && static_cast<int64_t>(u) >= min) return static_cast<int64_t>(u);
    fail(key, "expected " + range + ", got " + v.dump());
  }
  if (v.is_number_integer()) {
    int64_t x = v.get<int64_t>();
    if (x >= min && x <= max) return x;
    fail(key, "expected " + range + ", got " + v.dump());
  }
  if (v.is_number_float()) {
    double x = v.get<double>();
    if (std::isfinite(x) && x == std::floor(x) && x >= static_cast<double>(min) && x <= static_cast<double>(max))
      return static_cast<int64_t>(x);
    fail(key, "expected " + range + ", got " + v.dump());
  }
  fail(key, "expected " + range + ", got " + JsonKindName(v) + " " + v.dump());
}

int64_t Params::integer(const std::string& key, int64_t min, int64_t max, int64_t fallback) {
  mark_read(key);
  return has(key) ? integer(key, min, max) : fallback;
}

bool Params::boolean(const std::string& key, bool fallback) {
  mark_read(key);
  if (!has(key)) return fallback;
  const json& v = at(key);
  if (!v.is_boolean()) fail(key, "expected true or false, got " + JsonKindName(v) + " " + v.dump());
  return v.get<bool>();
}

std::string Params::string(const std::string& key) {
  const json& v = at(key);
  if (!v.is_string()) fail(key, "expected a string, got " + JsonKindName(v));
  return v.get<std::string>();
}

std::string Params::string(const std::string& key, const std::string& fallback) {
  mark_read(key);
  return has(key) ? string(key) : fallback;
}

std::string Params::choice(const std::string& key, const std::vector<std::string>& allowed,
                           const std::string& fallback) {
  std::string value = string(key, fallback);
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
    std::string msg = "\"" + value + "\" is not one of " + JoinWords(allowed);
    if (auto near = ClosestWord(value, allowed)) msg += "; did you mean \"" + *near + "\"?";
    fail(key, msg);
  }
  return value;
}

double Params::fraction_value(const json& v, const Location& loc) const {
  double x = quantity_value(v, loc, Dimension::kFraction);
  if (x < 0.0 || x > 1.0) throw Error(loc, "expected a fraction in [0, 1], got " + v.dump());
  return x;
}

Rgb Params::fraction_rgb(const std::string& key) {
  const json& v = at(key);
  Location loc = where_.child(key);
  if (v.is_array()) {
    if (v.size() != 3)
      throw Error(loc, "expected one fraction or three [r, g, b], got " + std::to_string(v.size()) + " values");
    return {fraction_value(v[0], loc.child(0)), fraction_value(v[1], loc.child(1)), fraction_value(v[2], loc.child(2))};
  }
  double x = fraction_value(v, loc);
  return {x, x, x};
}

Rgb Params::fraction_rgb(const std::string& key, double fallback) {
  mark_read(key);
  return has(key) ? fraction_rgb(key) : Rgb{fallback, fallback, fallback};
}

std::array<double, 2> Params::quantity_pair(const std::string& key, Dimension d, std::array<double, 2> fallback) {
  mark_read(key);
  if (!has(key)) return fallback;
  const json& v = at(key);
  Location loc = where_.child(key);
  if (v.is_array()) {
    if (v.size() != 2) throw Error(loc, "expected two values [x, y], got " + std::to_string(v.size()));
    return {quantity_value(v[0], loc.child(0), d), quantity_value(v[1], loc.child(1), d)};
  }
  double x = quantity_value(v, loc, d);
  return {x, x};
}

std::array<int64_t, 2> Params::integer_pair(const std::string& key, int64_t min, int64_t max) {
  const json& v = at(key);
  if (!v.is_array() || v.size() != 2)
    fail(key, "expected two integers [columns, rows], got " + JsonKindName(v) + " " + v.dump());
  Params pair_reader(json::object({{"0", v[0]}, {"1", v[1]}}), where_.child(key));
  return {pair_reader.integer("0", min, max), pair_reader.integer("1", min, max)};
}

Params Params::object(const std::string& key) {
  Params child(at(key), where_.child(key));
  child.owned_ = owned_;  // keeps an owned parent's storage alive
  return child;
}

void Params::require_range(const std::string& key, double value, double lo, double hi, bool lo_open,
                           bool hi_open) const {
  bool ok = (lo_open ? value > lo : value >= lo) && (hi_open ? value < hi : value <= hi);
  if (ok) return;
  auto bound = [](double b) {
    if (std::isinf(b)) return std::string(b > 0 ? "inf" : "-inf");
    std::string s = std::to_string(b);
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
    return s;
  };
  fail(key, "must be in " + std::string(lo_open ? "(" : "[") + bound(lo) + ", " + bound(hi) + (hi_open ? ")" : "]") +
                " (SI units), got " + bound(value));
}

void Params::check_all_read() const {
  std::vector<std::string> known(read_.begin(), read_.end());
  for (auto it = object_->begin(); it != object_->end(); ++it) {
    if (read_.count(it.key())) continue;
    std::string msg = "unknown key \"" + it.key() + "\"";
    if (auto near = ClosestWord(it.key(), known))
      msg += "; did you mean \"" + *near + "\"?";
    else if (!known.empty())
      msg += "; known keys: " + JoinWords(known, ", ");
    throw Error(where_.child(it.key()), msg);
  }
}

size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[b.size()];
}

std::optional<std::string> ClosestWord(const std::string& word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const std::string& c : candidates) {
    size_t d = EditDistance(word, c);
    if (d < best_distance) best_distance = d, best = c;
  }
  return best;
}

std::string JoinWords(const std::vector<std::string>& words, const std::string& last_sep) {
  std::string out;
  for (size_t i = 0; i < words.size(); ++i) {
    if (i > 0) out += (i + 1 == words.size()) ? last_sep : ", ";
    out += words[i];
  }
  return out;
}

}  // namespace layerlab

// The scene reader made from an option table (framework/option_table.h): one
// entry's key into its field, with the table's dimension, unit, range and
// choices; a key the field's default stands for when absent. Entries of kind
// kConfig are read by the section's reader by hand.
#pragma once

#include <string>
#include <vector>

#include "layerlab/framework/option_table.h"
#include "layerlab/framework/params.h"

namespace layerlab {

// The items of a non-empty array as a Params keyed "0", "1", ... at the
// array's own location, so that an item's error names /.../key/3.
Params ArrayItems(Params& p, const std::string& key);

// e's key, a non-empty array of quantities of e's dimension (a depth also as
// a distance, "0.5 m" is 2 D), in e's unit, each in e's range.
std::vector<double> ReadQuantityList(Params& p, const OptionSpec& e);

template <class Options>
void ReadOptionEntry(Params& p, const OptionEntry<Options>& e, Options* o) {
  switch (e.kind) {
    case OptionKind::kInteger:
      o->*e.integer = static_cast<int>(
          p.integer(e.key, static_cast<int64_t>(e.range.min), static_cast<int64_t>(e.range.max), o->*e.integer));
      break;
    case OptionKind::kSeed:
      if (p.has(e.key)) {
        const nlohmann::json& v = p.raw(e.key);
        if (!v.is_number_unsigned()) p.fail(e.key, "must be an integer in [0, 2^64 - 1], got " + v.dump());
        o->*e.seed = v.get<uint64_t>();
      }
      break;
    case OptionKind::kReal: {
      if (e.list) {
        p.mark_read(e.key);  // a known key, for the "did you mean" of a misspelt one
        if (p.has(e.key)) o->*e.list = ReadQuantityList(p, e);
        break;
      }
      const double unit = e.FieldUnitInSI();
      o->*e.real = p.quantity(e.key, e.dimension, o->*e.real * unit) / unit;
      p.require_range(e.key, o->*e.real, e.range.min, e.range.max, e.range.min_open, e.range.max_open);
      break;
    }
    case OptionKind::kChoice:
      e.set(*o, e.ChoiceIndex(p.choice(e.key, e.choices, e.choices[e.get(*o)])));
      break;
    case OptionKind::kBoolean:
      e.set(*o, p.boolean(e.key, e.get(*o) != 0));
      break;
    case OptionKind::kConfig:
      break;
  }
}

// Every entry of `table` that the scene holds (in_scene) but kConfig.
template <class Options>
void ReadOptionEntries(Params& p, const std::vector<OptionEntry<Options>>& table, Options* o) {
  for (const OptionEntry<Options>& e : table)
    if (e.in_scene) ReadOptionEntry(p, e, o);
}

}  // namespace layerlab

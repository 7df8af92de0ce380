// sweep: a design study, `layerlab sweep SWEEP.json --out DIR` (docs/sweeps.md).
// A base scene, named parameters with lists of values written into the scene
// at JSON pointers, and the work to run at every point of their grid.
//
//   { "format": "layerlab-sweep/1", "scene": "small/hybrid_small.json",
//     "parameters": [ { "name": "pupil", "pointer": "/elements/0/pupil_diameter", "values": ["3 mm", "5 mm"] } ],
//     "work": ["solve", "contrast"] }
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | format | string | required | `"layerlab-sweep/1"` |
// | name | string | the file's stem | title of the table and plots |
// | description | string | `""` | |
// | scene | path | required | the base scene (relative to this file); never modified |
// | parameters | array of parameters | required | the grid's axes in order, the last varying fastest |
// | work | array of `"solve"`, `"retina"`, `"contrast"` | required | what runs at each point, with the base scene's `run.retina` / `run.contrast` settings (their defaults when absent); `retina` needs `solve` |
// | iterations | integer | the scene's | outer iterations of each solve |
// | threads | integer | 1 | worker threads of each job (jobs run side by side) |
// | slurm | object | none | what `--slurm`'s scripts ask of Slurm (analysis/slurm_resources.h) |
//
// sweep.parameter: one axis of the grid
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | name | string | required | the table's column (unique) |
// | pointer | JSON pointer | required unless `pointers` | the scene value each value replaces; it must exist in the base scene |
// | pointers | array of JSON pointers | none | values set together: each value is then an array with one item per pointer |
// | values | array, not empty | required | any JSON: a quantity (`"1.2 D"`), a number, a name, a whole element object |
// | labels | array of strings | the values as written | what the table and plots show; labels that are all `"<number> <unit>"` in one unit become a numeric column `name (unit)` and a plot axis |
//
// A value at a path pointer (`/solve/target`, `/solve/target_scene`, a
// compared or contrast scene) is relative to the sweep file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/analysis/slurm_resources.h"

namespace layerlab {

inline constexpr const char* kSweepFormat = "layerlab-sweep/1";
inline constexpr size_t kMaxSweepPoints = 100000;  // a larger grid is refused as a mistake

struct SweepParameter {
  std::string name;
  std::vector<std::string> pointers;           // one, or several set together
  std::vector<nlohmann::ordered_json> values;  // with `pointers.size() > 1`: arrays of that size
  std::vector<std::string> labels;             // one per value
  // From the labels: the unit when every label is "<number> <unit>" in one unit, else empty.
  std::string unit;
  std::vector<double> numbers;  // the labels' numbers when `unit` is set
  std::string column() const;   // "name (unit)" or "name"
};

struct SweepSpec {
  std::string file;  // as given
  std::string name;
  bool named = false;  // the file gives "name" (else the name is its stem)
  std::string description;
  std::string scene;  // resolved against the sweep file's folder
  std::vector<SweepParameter> parameters;
  bool solve = false, retina = false, contrast = false;
  std::optional<int> iterations;
  int threads = 1;
  SlurmResources slurm;
  nlohmann::ordered_json base;  // the base scene's document, in file order
  // The product of the parameters' value counts; throws layerlab::Error at
  // /parameters when it does not fit in 64 bits.
  size_t job_count() const;
  std::vector<std::string> work() const;  // "solve", "retina", "contrast" as declared
};

// Reads and checks the sweep file and its base scene; throws layerlab::Error
// naming the file and the JSON pointer (an unknown key, a pointer that is not
// in the scene, an empty list, unknown work).
SweepSpec ReadSweepSpec(const std::string& path);

}  // namespace layerlab

// optimize: a display design problem, `layerlab optimize DESIGN.json --out DIR`
// (docs/optimize.md). A base scene, the scene values that vary (by JSON pointer,
// with bounds in a unit), constraints, and the objective the optimizer
// minimizes: metrics of each evaluated design, each a `layerlab run` of the
// scene with the values written in (the sweep's jobs, analysis/sweep_jobs.h).
//
//   { "format": "layerlab-design/1", "scene": "../small/hybrid_small.json",
//     "variables": [ { "name": "rear", "pointer": "/elements/4/virtual_depth", "min": "0.2 D", "max": "1.2 D" } ],
//     "objective": "psnr" }
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | format | string | required | `"layerlab-design/1"` |
// | name | string | the file's stem | title of the report and plots |
// | description | string | `""` | |
// | scene | path | required | the base scene (relative to this file); never modified |
// | variables | array of variables | required | what the optimizer varies |
// | constraints | array of constraints | `[]` | what a design must satisfy |
// | fixed | object `{pointer: value}` | `{}` | values written into the base scene (any JSON but a path: `{"/elements/2/fill_factor": 0.75}`; new where their parent object exists), so that a variant of the scene needs no copy |
// | objective | metric name or object | required | `"psnr"`, or `{ "terms": [ { "metric": "psnr", "weight": 1 }, ... ] }` |
// | targets | array of paths | the scene's own | target scenes (`/solve/target_scene`); each design is evaluated on every one and its metrics averaged |
// | iterations | integer | the scene's | outer iterations of each solve |
// | threads | integer | 0 (all cores) | worker threads of each evaluation |
// | optimizer | object | below | the algorithm and the budget |
// | warm_start | boolean | true | each solve starts from the patterns of the nearest design evaluated so far (when the layers' shapes match) |
//
// design.variable
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | name | string | required | the history's column (unique) |
// | pointer | JSON pointer | required unless `pointers` | the scene value the variable sets; it must exist in the base scene |
// | pointers | array of `{pointer, scale, offset}` | none | values set together, each `scale x + offset` (a spacing that moves two layers) |
// | min, max | quantity | required | the bounds, in the variable's unit (`"0.2 D"`, `"60 mm"`, or a plain number) |
// | start | quantity | the scene's value when it is in the unit and the bounds, else the middle | where the local search starts |
// | tolerance | quantity | (max - min) / 1000 | the step below which the search stops |
//
// design.constraint: either linear in the variables, or on a metric of the evaluated design
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | name | string | required | named in messages and the history |
// | terms | object `{variable: coefficient}` | required unless `metric` | the constraint is on sum(coefficient x variable), in the variables' common unit |
// | metric | metric name | none | the constraint is on that metric of the design (docs/optimize.md lists them) |
// | min, max | quantity | at least one | the bound(s), in the unit of the terms or the metric |
//
// design.objective.term: `{ "metric": NAME, "weight": w }`, weight > 0 (default 1).
// The optimizer minimizes sum(w x v) over the terms, v counted negative for a
// metric where higher is better; a single term is reported as its metric.
//
// design.optimizer
//
// | key | type | default | meaning |
// | --- | --- | --- | --- |
// | local | `"cobyla"`, `"bobyqa"`, `"nelder-mead"`, `"slsqp"` | `"cobyla"` | NLopt's local search: derivative-free (constraints go to COBYLA directly and to the others through an augmented Lagrangian), or SLSQP on the exact gradient of the solve's PSNR (design/design_gradient.h; linear constraints only) |
// | global | `"none"`, `"mlsl"`, `"crs"`, `"multistart"` | `"none"` | a global stage for problems with local optima: MLSL's multistart from a low-discrepancy sequence, controlled random search (CRS2), or independent local searches from `starts` points (design/design_starts.h), which the runners of `optimize --local/--mpi/--slurm` run in parallel |
// | starts | integer, 2-256 | 4 | with `"multistart"`: the local searches, the first from the design's start |
// | evaluations | integer | 60 | the budget in evaluations (each a solve per target); a multistart's is split among its starts |
// | seconds | number | none | a budget in wall time |
// | seed | integer | 1 | of the global stage's random numbers (a resumed run replays them) |
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/design/design_metrics.h"

namespace layerlab {

inline constexpr const char* kDesignFormat = "layerlab-design/1";
inline constexpr size_t kMaxDesignVariables = 32;     // more is refused as a mistake
inline constexpr size_t kMaxDesignConstraints = 256;  // likewise

struct DesignWrite {  // one scene value a variable sets: scale x + offset
  std::string pointer;
  double scale = 1, offset = 0;
};

struct DesignVariable {
  std::string name;
  std::string unit;  // as written ("D", "mm"); empty for a plain number
  std::vector<DesignWrite> writes;
  double min = 0, max = 0, start = 0, tolerance = 0;
  std::string column() const;  // "name (unit)"
  // The scene value written for x: "1.25 D", or a number when there is no unit.
  nlohmann::ordered_json SceneValue(double x) const;
};

struct DesignConstraint {
  std::string name;
  std::string unit;
  std::vector<double> coefficients;  // per variable; empty for a metric constraint
  std::optional<size_t> metric;      // index into DesignSpec::metrics
  std::optional<double> min, max;
  // What the constraint bounds, for messages: "front - rear (D)", "brightness (cd/m2)".
  std::string what;
};

struct DesignTerm {
  size_t metric = 0;  // index into DesignSpec::metrics
  double weight = 1;
};

struct DesignOptimizer {
  std::string local = "cobyla", global = "none";
  int evaluations = 60;
  int starts = 1;  // > 1 only for "multistart"
  std::optional<double> seconds;
  unsigned seed = 1;
};

// Why the budget cannot be spent as asked ("" when it can): a multistart needs an evaluation per start.
std::string BudgetProblem(const DesignOptimizer& o);

struct DesignSpec {
  std::string file, name, description;
  std::string scene;  // resolved against the design file's folder
  std::vector<DesignVariable> variables;
  std::vector<DesignConstraint> constraints;
  std::vector<DesignMetric> metrics;  // every metric the objective and constraints read, once each
  std::vector<DesignTerm> objective;
  std::vector<std::string> targets;  // absolute target scenes; empty: the scene's own
  std::optional<int> iterations;
  int threads = 0;
  bool warm_start = true;
  DesignOptimizer optimizer;
  nlohmann::ordered_json base;                                          // the base scene's document, in file order
  bool work_solve = false, work_retina = false, work_contrast = false;  // what the metrics need

  // The objective's name with its unit: "PSNR (dB)" for one term, "weighted sum (1)" for several.
  std::string objective_column() const;
};

// Reads and checks the design file and its base scene; throws layerlab::Error
// naming the file and the JSON pointer.
DesignSpec ReadDesignSpec(const std::string& path);

}  // namespace layerlab

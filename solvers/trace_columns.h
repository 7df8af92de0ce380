// The columns of a solve's trace (IterationRecord), described once: each
// column's name (the key of report.json's trace and of Python's trace dict,
// the column of trace.csv and of compare's traces.csv, an entry of a
// checkpoint's trace row), unit and printing. A new per-iteration metric is a
// field of IterationRecord, its row in kTraceColumns' table and the line of
// SolveLoop that measures it; every writer of a trace reads the table.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/solvers/types.h"

namespace layerlab {

enum class TraceValueKind {
  kCount,      // an integer, printed %d
  kSeconds,    // wall time, printed %.6f
  kObjective,  // a sum of squares, printed %.9g
  kDecibels,   // a PSNR, printed %.6f ("inf" for a perfect fit)
  kScore,      // a perceptual metric, printed %.6f
};

struct TraceColumn {
  const char* name;
  const char* unit;  // "" for none
  const char* meaning;
  TraceValueKind kind;
  double (*value)(const IterationRecord&);
  void (*set)(IterationRecord*, double);
  // NaN where the solve did not measure it; trace.csv and report.json leave
  // the column out of a trace that never measured it.
  bool measured_only;
};

// The columns, in the order the files write them.
const std::vector<TraceColumn>& TraceColumns();
// The column of a focal stack's metric ("focal_stack_" and its column; psnr: focal_stack_psnr_db).
const TraceColumn& FocalStackColumn(const RetinalMetric& metric);

// Whether any row of `trace` measured the column (always, unless measured_only).
bool Measured(const TraceColumn& column, const std::vector<IterationRecord>& trace);

// The columns a trace's files write: every column it measured.
std::vector<const TraceColumn*> WrittenColumns(const std::vector<IterationRecord>& trace);

// One value as trace.csv prints it; `decibel_decimals` the digits of a PSNR
// (compare's traces.csv prints 3). NaN: "nan" (trace.csv) or, with
// `nan_as_empty`, nothing.
std::string TraceField(const TraceColumn& column, double value, int decibel_decimals = 6, bool nan_as_empty = false);

// One value of `row` as report.json's trace and checkpoints hold it: a count
// as an integer, an infinity as "inf" or "-inf" (JsonNumber), NaN as null.
nlohmann::json TraceJson(const TraceColumn& column, const IterationRecord& row);

}  // namespace layerlab

// The trace's columns (solvers/trace_columns.h) against each field of
// IterationRecord, and the files a trace is written to against the table.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>

#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/trace_columns.h"

namespace layerlab {
namespace {

// A record whose fields all differ, and each field's value by its column's name, written here apart from the table.
IterationRecord DistinctRecord() { return {7, 1.5, 42.25, 31.125, 27.0625, 0.875, 0.9375, 12.5}; }
double FieldNamed(const IterationRecord& r, const std::string& name) {
  if (name == "iteration") return r.iteration;
  if (name == "seconds") return r.seconds;
  if (name == "objective") return r.objective;
  if (name == "psnr_db") return r.psnr_db;
  if (name == "focal_stack_psnr_db") return r.focal_stack_psnr_db;
  if (name == "focal_stack_ssim") return r.focal_stack_ssim;
  if (name == "focal_stack_ms_ssim") return r.focal_stack_ms_ssim;
  if (name == "focal_stack_jnd") return r.focal_stack_jnd;
  ADD_FAILURE() << "no field for column " << name;
  return NAN;
}

TEST(TraceColumns, EachColumnReadsAndWritesItsOwnField) {
  std::set<std::string> names;
  for (const TraceColumn& c : TraceColumns()) {
    EXPECT_TRUE(names.insert(c.name).second) << "two columns named " << c.name;
    const IterationRecord r = DistinctRecord();
    EXPECT_EQ(c.value(r), FieldNamed(r, c.name)) << c.name;
    IterationRecord changed = r;
    c.set(&changed, 3);
    EXPECT_EQ(FieldNamed(changed, c.name), 3) << c.name;
    for (const TraceColumn& other : TraceColumns()) {
      if (&other == &c) continue;
      EXPECT_EQ(other.value(changed), other.value(r)) << c.name << " wrote " << other.name;
    }
  }
  EXPECT_EQ(names.size(), 8u) << "a new column: add its field to FieldNamed";
}

TEST(TraceColumns, TraceCsvAndReportJsonWriteTheTablesColumns) {
  SolverReport report;
  report.solver = "x";
  report.trace = {{0, 0.0, 12.5, 21.25}, {1, 0.125, 3.75, INFINITY}};
  EXPECT_EQ(TraceCsv(report),
            "iteration,seconds,objective,psnr_db\n"
            "0,0.000000,12.5,21.250000\n"
            "1,0.125000,3.75,inf\n");
  // A trace that measured the focal stack has its column too.
  report.trace[0].focal_stack_psnr_db = 18.5, report.trace[1].focal_stack_psnr_db = 19.75;
  EXPECT_EQ(TraceCsv(report),
            "iteration,seconds,objective,psnr_db,focal_stack_psnr_db\n"
            "0,0.000000,12.5,21.250000,18.500000\n"
            "1,0.125000,3.75,inf,19.750000\n");
  // And one that measured a metric of it in some rows, that column, empty where not measured ("nan").
  report.trace[1].focal_stack_jnd = 2.5;
  EXPECT_EQ(TraceCsv(report),
            "iteration,seconds,objective,psnr_db,focal_stack_psnr_db,focal_stack_jnd\n"
            "0,0.000000,12.5,21.250000,18.500000,nan\n"
            "1,0.125000,3.75,inf,19.750000,2.500000\n");
  const nlohmann::json rows = ReportToJson(report)["trace"];
  ASSERT_EQ(rows.size(), 2u);
  for (const TraceColumn* c : WrittenColumns(report.trace)) ASSERT_TRUE(rows[1].contains(c->name)) << c->name;
  EXPECT_EQ(rows[1].size(), 6u);
  EXPECT_EQ(rows[0]["focal_stack_jnd"].dump(), "null");  // NaN, written as null
  EXPECT_EQ(rows[1]["iteration"], 1);
  EXPECT_TRUE(rows[1]["iteration"].is_number_integer());
  EXPECT_EQ(rows[1]["psnr_db"], "inf");
  EXPECT_EQ(rows[1]["focal_stack_psnr_db"], 19.75);
}

TEST(TraceColumns, EachKindIsPrintedAsItsFilesPrintIt) {
  const auto& columns = TraceColumns();
  auto named = [&](const std::string& name) -> const TraceColumn& {
    for (const TraceColumn& c : columns)
      if (name == c.name) return c;
    throw std::runtime_error(name);
  };
  EXPECT_EQ(TraceField(named("iteration"), 12), "12");
  EXPECT_EQ(TraceField(named("seconds"), 1.0 / 3), "0.333333");
  EXPECT_EQ(TraceField(named("objective"), 1.0 / 3), "0.333333333");
  EXPECT_EQ(TraceField(named("psnr_db"), 1.0 / 3), "0.333333");
  EXPECT_EQ(TraceField(named("psnr_db"), 1.0 / 3, 3), "0.333");
  EXPECT_EQ(TraceField(named("psnr_db"), -INFINITY), "inf");
  EXPECT_EQ(TraceField(named("focal_stack_psnr_db"), NAN, 3, true), "");
  EXPECT_EQ(TraceField(named("focal_stack_psnr_db"), NAN), "nan");
  EXPECT_EQ(TraceField(named("focal_stack_ms_ssim"), 1.0 / 3), "0.333333");
}

}  // namespace
}  // namespace layerlab

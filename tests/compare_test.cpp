// `compare` with objectives (analysis/compare.h): each solver runs each
// objective it minimizes, and every row of a comparison that includes the
// retinal objective carries both PSNRs, in the table, the CSVs and the plot.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "layerlab/analysis/compare.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

const std::vector<ObjectiveKind> kBoth = {ObjectiveKind::kLightField, ObjectiveKind::kRetinal};

TEST(Compare, EachSolverRunsEachObjectiveItMinimizes) {
  std::vector<std::string> skipped;
  const std::vector<CompareRun> runs =
      CompareRunsOf({testing::ExamplePath("paper_prototype.json")},
                    {{"hybrid", "quasi-newton"}, 2, std::nullopt, false, kBoth, {}, {}}, &skipped);
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(RunLabel(runs[0].display, runs[0].solver, runs[0].options.objective), "paper_prototype / hybrid");
  EXPECT_EQ(RunLabel(runs[1].display, runs[1].solver, runs[1].options.objective), "paper_prototype / quasi-newton");
  EXPECT_EQ(RunLabel(runs[2].display, runs[2].solver, runs[2].options.objective),
            "paper_prototype / quasi-newton / retinal");
  // The light-field runs measure the focal stack, so that every row has both PSNRs.
  EXPECT_TRUE(runs[0].options.measure_focal_stack);
  EXPECT_TRUE(runs[1].options.measure_focal_stack);
  EXPECT_FALSE(runs[2].options.measure_focal_stack);
  for (const CompareRun& r : runs) EXPECT_EQ(r.options.iterations, 2);
  EXPECT_EQ(skipped, (std::vector<std::string>{
                         "paper_prototype / hybrid / retinal: the solver \"hybrid\" minimizes the light-field "
                         "objective only; the retinal objective needs joint or quasi-newton"}));

  // Without objectives: the light field's, nothing measured off the clock.
  const std::vector<CompareRun> plain = CompareRunsOf({testing::ExamplePath("paper_prototype.json")},
                                                      {{"quasi-newton"}, 2, std::nullopt, false, {}, {}, {}}, nullptr);
  ASSERT_EQ(plain.size(), 1u);
  EXPECT_EQ(plain[0].options.objective, ObjectiveKind::kLightField);
  EXPECT_FALSE(plain[0].options.measure_focal_stack);
  // Light field alone, named: no focal stack either (no row minimizes it).
  EXPECT_FALSE(
      WithObjective(SolverOptions{}, ObjectiveKind::kLightField, {ObjectiveKind::kLightField}).measure_focal_stack);
}

TEST(Compare, EveryRowCarriesBothPsnrsWhenOneMinimizesTheFocalStack) {
  const DisplaySystem stack = testing::CompileJson(testing::ShrunkExample("multiplicative_2layer.json", 16, 8, 3));
  const DisplayModel model(stack, DisplayLightFieldGeometry(stack));
  Patterns truth = model.UniformPatterns(0.5f);
  for (LayerPattern& p : truth)
    for (size_t k = 0; k < p.rgb.size(); ++k) p.rgb[k] = 0.3f + 0.6f * float((k * 7919) % 101) / 100.0f;
  // Beyond the display's reach (a speckle on every ray), so that the two objectives lead to different patterns.
  LightField target = Synthesize(model, truth);
  for (size_t k = 0; k < target.rgb.size(); ++k) target.rgb[k] *= 0.8f + 0.4f * float((k * 2654435761u) % 97) / 96.0f;
  SolverOptions o;
  o.iterations = 40;
  o.warm_start_iterations = 0;
  std::vector<CompareRun> runs;
  for (ObjectiveKind k : kBoth) runs.push_back({"stack", stack, "quasi-newton", WithObjective(o, k, kBoth)});
  const std::vector<CompareResult> results = RunComparison(runs, target);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].report.objective, "lightfield");
  EXPECT_EQ(results[1].report.objective, "retinal");
  for (const CompareResult& r : results) {
    ASSERT_TRUE(r.report.IsSolutionUsable()) << r.report.FullReport();
    for (const IterationRecord& row : r.report.trace) EXPECT_TRUE(std::isfinite(row.focal_stack_psnr_db));
    EXPECT_EQ(FinalFocalStackPsnr(r.report), r.report.trace.back().focal_stack_psnr_db);
  }
  // The retinal solve minimizes the focal stack's error: it ends higher there than the light-field solve.
  EXPECT_GT(FinalFocalStackPsnr(results[1].report), FinalFocalStackPsnr(results[0].report)) << CompareTable(results);

  const std::string csv = CompareCsv(results);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "display,solver,objective,final_psnr_db,final_focal_stack_psnr_db,seconds,iterations,subframes,"
            "panel_refresh_hz,luminance_efficiency,efficiency_r,efficiency_g,efficiency_b,termination,solver_options");
  EXPECT_NE(csv.find("\nstack,quasi-newton,retinal," + FormatPsnr(results[1].report.final_psnr_db, 3) + "," +
                     FormatPsnr(FinalFocalStackPsnr(results[1].report), 3) + ","),
            std::string::npos)
      << csv;
  const std::string traces = TracesCsv(results);
  EXPECT_EQ(traces.substr(0, traces.find('\n')),
            "display,solver,objective_kind,iteration,seconds,objective,psnr_db,focal_stack_psnr_db");
  EXPECT_NE(traces.find("\nstack,quasi-newton,retinal,0,"), std::string::npos) << traces;
  const std::string svg = PsnrAgainstTimeSvg(results);
  EXPECT_NE(svg.find("light-field PSNR against wall time"), std::string::npos);
  EXPECT_NE(svg.find("focal-stack PSNR against wall time"), std::string::npos);
  EXPECT_NE(svg.find("stack / quasi-newton / retinal"), std::string::npos);
  EXPECT_NE(CompareTable(results).find("retinal"), std::string::npos);

  // A light-field comparison has no focal-stack column values and no second panel.
  runs = {{"stack", stack, "quasi-newton", o}};
  const std::vector<CompareResult> plain = RunComparison(runs, target);
  EXPECT_TRUE(std::isnan(FinalFocalStackPsnr(plain[0].report)));
  EXPECT_NE(CompareCsv(plain).find(",lightfield," + FormatPsnr(plain[0].report.final_psnr_db, 3) + ",,"),
            std::string::npos)
      << CompareCsv(plain);
  EXPECT_EQ(PsnrAgainstTimeSvg(plain).find("focal-stack"), std::string::npos);
}

// A solution's eyebox in the comparison: the pupil positions are those that
// keep the 4 mm pupil inside the light field's 6 mm eyebox (1 mm each way in
// steps of 0.5 mm); a display that shows its target exactly is within any
// quality across them, and the table and CSV gain its column.
// The plot's axis reaches iteration 0 (issue 50: a flat initial guess at 14 dB was drawn at the
// axis' foot, 29 dB, so that the curve seemed to start high).
TEST(Compare, PsnrAgainstTimeShowsIterationZero) {
  CompareResult r;
  r.display = "d", r.solver = "hybrid";
  for (const auto& [iteration, psnr] : {std::pair{0, 14.0}, {1, 30.0}, {2, 31.0}, {3, 32.0}}) {
    IterationRecord row;
    row.iteration = iteration, row.seconds = 0.5 * iteration, row.psnr_db = psnr;
    r.report.trace.push_back(row);
  }
  const std::string svg = PsnrAgainstTimeSvg({r});
  EXPECT_NE(svg.find(">15<"), std::string::npos) << "no tick below 29 dB: " << svg;
}

TEST(Compare, TheEyeboxColumnCoversThePupilPositionsInsideTheLightField) {
  const DisplaySystem stack = testing::CompileJson(testing::ShrunkExample("multiplicative_2layer.json", 16, 8, 3));
  const DisplayModel model(stack, DisplayLightFieldGeometry(stack));
  const LightField target = Synthesize(model, model.UniformPatterns(0.5f));
  SolverOptions o;
  o.iterations = 3;
  CompareEyebox eyebox;
  eyebox.accommodation_diopters = 1.0;
  const std::vector<CompareResult> results =
      RunComparison({{"stack", stack, "multiplicative", o}}, target, false, SolverRegistry::Builtins(), eyebox);
  ASSERT_TRUE(results[0].eyebox);
  EXPECT_DOUBLE_EQ(results[0].eyebox->within_m[0], 2e-3);
  EXPECT_DOUBLE_EQ(results[0].eyebox->within_m[1], 2e-3);
  EXPECT_TRUE(results[0].eyebox->reaches_edge[0]);
  EXPECT_NE(CompareTable(results).find(">= 2.00 x >= 2.00 mm"), std::string::npos) << CompareTable(results);
  EXPECT_NE(CompareCsv(results).find(",2.0000,2.0000,1,1\n"), std::string::npos) << CompareCsv(results);
  // Without the option nothing is measured and the table is as before.
  const std::vector<CompareResult> plain = RunComparison({{"stack", stack, "multiplicative", o}}, target);
  EXPECT_FALSE(plain[0].eyebox);
  EXPECT_EQ(CompareTable(plain).find("eyebox"), std::string::npos);
}

// The panels' diffraction the scene's solve asks for is the display's
// physics: every row solves through it, and a solver that cannot is left out, saying why.
TEST(Compare, EveryRowSolvesThroughThePanelsDiffractionOrIsLeftOut) {
  nlohmann::json scene = testing::ReadExample("paper_prototype.json");
  for (nlohmann::json& e : scene["elements"])
    if (e["type"] == "lc_panel") e["fill_factor"] = 0.75;
  scene["solve"]["panel_diffraction"] = true;
  scene["solve"].erase("target_scene");
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("layerlab_compare_diffracted_" + std::to_string(::getpid()) + ".json");
  std::ofstream(file) << scene.dump();
  std::vector<std::string> skipped;
  const std::vector<CompareRun> runs =
      CompareRunsOf({file.string()}, {{"hybrid", "joint"}, 2, std::nullopt, false, {}, {}, {}}, &skipped);
  std::filesystem::remove(file);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].solver, "joint");
  EXPECT_TRUE(runs[0].options.panel_diffraction);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find("hybrid: the solver does not model the panels' diffraction"), std::string::npos)
      << skipped[0];
}

}  // namespace
}  // namespace layerlab

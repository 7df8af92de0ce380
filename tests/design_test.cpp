// layerlab optimize (design/): the design file's checks, the constraints'
// feasibility, the metrics read from a run's row, and the search on problems
// whose optimum is known: one layer and a grating on one plane (its depth),
// and two layers against a dense grid of the same evaluations.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>

#include "layerlab/design/design_evaluator.h"
#include "layerlab/design/design_gradient.h"
#include "layerlab/design/design_search.h"
#include "layerlab/design/design_starts.h"
#include "layerlab/design/placement_gradient.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/scene.h"
#include "test_util.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using layerlab::testing::ErrorOf;
using layerlab::testing::ExamplePath;
using layerlab::testing::ReadExample;

std::string Scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_design_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

// A design file beside the example scenes (so that "scene" resolves), with `edit` applied.
std::string DesignFile(const std::string& name, const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json d = ReadExample("optimize/two_layer_depths.json");
  edit(d);
  d["scene"] = ExamplePath("optimize/two_layer_small.json");
  const std::string path = Scratch(name) + "/design.json";
  std::ofstream(path) << d.dump(2);
  return path;
}

std::string DesignError(const std::function<void(nlohmann::json&)>& edit) {
  return ErrorOf([&] { CheckDesignFeasible(ReadDesignSpec(DesignFile("error", edit))); });
}

TEST(DesignSpec, ReadsTheExample) {
  const DesignSpec spec = ReadDesignSpec(ExamplePath("optimize/two_layer_depths.json"));
  ASSERT_EQ(spec.variables.size(), 2u);
  EXPECT_EQ(spec.variables[0].unit, "D");
  EXPECT_DOUBLE_EQ(spec.variables[0].start, 1.6);  // the scene's value, in the bounds
  EXPECT_DOUBLE_EQ(spec.variables[1].start, 0.8);
  EXPECT_EQ(spec.variables[0].SceneValue(1.25).get<std::string>(), "1.25 D");
  ASSERT_EQ(spec.constraints.size(), 1u);
  EXPECT_EQ(spec.constraints[0].what, "front - rear (D)");
  EXPECT_EQ(spec.objective_column(), "psnr (dB)");
  EXPECT_TRUE(spec.work_solve);
  EXPECT_FALSE(spec.work_contrast);
}

TEST(DesignSpec, RefusesWithTheFileAndPointer) {
  EXPECT_NE(DesignError([](auto& d) {
              d["variables"][0]["pointer"] = "/elements/2/virtual_dept";
            }).find("/variables/0/pointer: \"/elements/2/virtual_dept\" is not in the scene"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["variables"][0]["max"] = "400 mm";
            }).find("/variables/0/max: is in \"mm\", but \"min\" is in \"D\""),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) { d["variables"][0]["min"] = "0.6 Dpt"; }).find("unknown unit \"Dpt\""),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) { d["variables"][1]["max"] = "0.1 D"; }).find("/variables/1/max: must be above"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) { d["objective"] = "psnrr"; }).find("/objective: unknown metric \"psnrr\""),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["constraints"][0]["terms"] = {{"middle", 1}};
            }).find("/constraints/0/terms/middle: \"middle\" is not a variable"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) { d["variables"][0]["strat"] = "1 D"; }).find("strat"), std::string::npos);
  EXPECT_NE(
      DesignError([](auto& d) { d["variables"][1]["pointer"] = "/elements/2/virtual_depth"; })
          .find("/variables/1/pointer: \"/elements/2/virtual_depth\" overlaps \"/elements/2/virtual_depth\", which the "
                "variable \"front\" sets"),
      std::string::npos);
  EXPECT_NE(DesignError([](auto& d) { d["variables"][1]["pointer"] = "/elements/2"; }).find("overlaps"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["variables"][1]["pointer"] = "/elements/2/reversed";
            }).find("holds a boolean in the scene; a variable replaces a number or a quantity"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["variables"][1]["pointer"] = "/elements/0/pupil_diameter";
            }).find("/variables: the base scene with the variables at their starts is not usable"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) { d["constraints"][0]["max"] = "0.3 D"; }).find("/constraints/0/max: equals"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["variables"][0]["start"] = "0.9 D";
            }).find("/constraints/0: the start (front 0.9 D, rear 0.8 D) does not meet \"front before rear\""),
            std::string::npos);
}

TEST(DesignSpec, FixedValuesAreWrittenIntoTheBaseScene) {
  const DesignSpec spec = ReadDesignSpec(DesignFile("fixed", [](auto& d) {
    d["fixed"] = {{"/elements/2/fill_factor", 0.75}, {"/run", {{"retina", {{"accommodation", {"0.5 D", "1.5 D"}}}}}}};
    d["objective"] = "focal_stack_ssim";
  }));
  EXPECT_EQ(spec.base["elements"][2]["fill_factor"], 0.75);
  EXPECT_EQ(spec.base["run"]["retina"]["accommodation"][1], "1.5 D");
  EXPECT_TRUE(spec.work_retina);
  EXPECT_NE(DesignError([](auto& d) {
              d["fixed"] = {{"/elements/2/virtual_depth", "1 D"}};
            }).find("/fixed/~1elements~12~1virtual_depth: holds what the variable \"front\" sets"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["fixed"] = {{"/elements/2/fill_factor", "most"}};
            }).find("/fixed: the base scene with these values is not usable"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["fixed"] = {{"/nothing/here", 1}};
            }).find("nor is the object it would go in"),
            std::string::npos);
  // Without retinal states of its own the scene would look at the layers, which the optimizer moves.
  EXPECT_NE(DesignError([](auto& d) {
              d["objective"] = "focal_stack_psnr";
            }).find("/objective: a retinal metric is a mean over the retinal states"),
            std::string::npos);
}

TEST(DesignSpec, AMultistartNeedsAnEvaluationPerStart) {
  EXPECT_NE(DesignError([](auto& d) {
              d["optimizer"] = {{"global", "multistart"}, {"starts", 6}, {"evaluations", 5}};
            }).find("/optimizer/evaluations: is 5: fewer evaluations than the 6 starts"),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["optimizer"] = {{"global", "crs"}, {"starts", 6}};
            }).find("/optimizer/starts: is read only with \"global\": \"multistart\""),
            std::string::npos);
  EXPECT_NE(DesignError([](auto& d) {
              d["optimizer"] = {{"global", "multistart"}, {"starts", 1}};
            }).find("/optimizer/starts"),
            std::string::npos);
}

TEST(DesignStarts, BeginAtTheStartThenFillTheFeasibleBox) {
  DesignSpec spec = ReadDesignSpec(DesignFile("starts", [](auto& d) {
    d["optimizer"] = {{"global", "multistart"}, {"starts", 12}, {"evaluations", 40}};
  }));
  const std::vector<std::vector<double>> points = MultistartPoints(spec);
  ASSERT_EQ(points.size(), 12u);
  EXPECT_EQ(points[0], (std::vector<double>{1.6, 0.8}));
  // Halton, seed 1: index 2 is (1/4, 2/3) of the box, front 1.05 D and rear 1.133 D, which misses
  // front - rear >= 0.3 D; index 3 is (3/4, 1/9): 1.95 D and 0.3556 D.
  EXPECT_NEAR(points[1][0], 0.6 + 0.75 * 1.8, 1e-12);
  EXPECT_NEAR(points[1][1], 0.2 + 1.4 / 9, 1e-12);
  double lowest_front = INFINITY, highest_front = -INFINITY;
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_GE(points[i][0], 0.6);
    EXPECT_LE(points[i][0], 2.4);
    EXPECT_GE(points[i][1], 0.2);
    EXPECT_LE(points[i][1], 1.6);
    EXPECT_GE(points[i][0] - points[i][1], 0.3 - 1e-12) << i;
    for (size_t j = 0; j < i; ++j) EXPECT_NE(points[i], points[j]) << i << " " << j;
    lowest_front = std::min(lowest_front, points[i][0]);
    highest_front = std::max(highest_front, points[i][0]);
  }
  EXPECT_LT(lowest_front, 1.0);  // spread over the box, not bunched
  EXPECT_GT(highest_front, 2.0);
  EXPECT_EQ(MultistartPoints(spec), points);
  spec.optimizer.seed = 5;  // the sequence from index 6: (3/8, 2/9) of the box
  EXPECT_NEAR(MultistartPoints(spec)[1][0], 0.6 + 0.375 * 1.8, 1e-12);
  EXPECT_NEAR(MultistartPoints(spec)[1][1], 0.2 + 1.4 * 2 / 9, 1e-12);
  spec.optimizer.evaluations = 42;  // 4 x 3 + 30 left: 42 / 12 = 3, the first six take one more
  int sum = 0;
  for (int k = 0; k < 12; ++k) sum += StartBudget(spec, k);
  EXPECT_EQ(sum, 42);
  EXPECT_EQ(StartBudget(spec, 0), 4);
  EXPECT_EQ(StartBudget(spec, 5), 4);
  EXPECT_EQ(StartBudget(spec, 6), 3);
  EXPECT_EQ(StartId(7), "s07");
}

TEST(DesignFeasibility, AConstraintNoDesignMeetsIsNamedWithItsRange) {
  // front - rear reaches at most 2.4 - 0.2 = 2.2 D within the bounds.
  const std::string e = DesignError([](auto& d) { d["constraints"][0]["min"] = "2.5 D"; });
  EXPECT_NE(e.find("/constraints/0: no design meets \"front before rear\": front - rear (D) must be at least 2.5 D, "
                   "but within the variables' bounds it is at most 2.2 D"),
            std::string::npos)
      << e;
  EXPECT_EQ(DesignError([](auto& d) {  // the corner meets it, and starts there
              d["constraints"][0]["min"] = "2.2 D";
              d["variables"][0]["start"] = "2.4 D";
              d["variables"][1]["start"] = "0.2 D";
            }),
            "no error");
}

TEST(DesignFeasibility, ConstraintsThatExcludeEveryDesignTogetherAreNamed) {
  // Each alone is met somewhere; together they are not (the third is met where they come closest).
  const std::string tight = DesignError([](auto& d) {
    d["constraints"][0]["min"] = "1.5 D";
    d["constraints"].push_back({{"name", "short track"}, {"terms", {{"front", 1}, {"rear", 1}}}, {"max", "1.6 D"}});
    d["constraints"].push_back({{"name", "unrelated"}, {"terms", {{"rear", 1}}}, {"max", "1.5 D"}});
  });
  EXPECT_NE(
      tight.find("/constraints/0: no design meets the constraints \"front before rear\", \"short track\" together"),
      std::string::npos)
      << tight;
  EXPECT_EQ(tight.find("unrelated"), std::string::npos) << tight;
  // Both miss by t: front - rear >= 1.5 - t, front + rear <= 1.6 + t at rear = 0.2 give
  // 1.7 - t <= front <= 1.4 + t, so t = 0.15.
  EXPECT_NE(tight.find("still misses each by 0.15"), std::string::npos) << tight;
}

TEST(DesignMetrics, AreReadFromARunsRow) {
  std::vector<SweepResult> row(5);
  row[0] = {kPsnrColumn, 31.5, std::nullopt};
  row[1] = {std::string(kPeakAccommodationColumn) + "0.7 D, 2 cpd (D)", 0.8, 0.7};
  row[2] = {std::string(kPeakAccommodationColumn) + "1.9 D, 2 cpd (D)", 1.6, 1.9};
  row[3] = {std::string(kRetinalMeanColumn) + "0.4 D (cd/m2)", 20.0, std::nullopt};
  row[4] = {std::string(kRetinalMeanColumn) + "2.2 D (cd/m2)", 30.0, std::nullopt};
  auto value = [&](const std::string& name) {
    std::string error;
    const auto m = FindDesignMetric(name, &error);
    EXPECT_TRUE(m) << error;
    return MetricValue(*m, row);
  };
  EXPECT_DOUBLE_EQ(*value("psnr"), 31.5);
  EXPECT_NEAR(*value("accommodation_error"), (0.1 + 0.3) / 2, 1e-15);
  EXPECT_DOUBLE_EQ(*value("brightness"), 25.0);
  EXPECT_FALSE(value("peak_contrast"));  // not in the row: the evaluation fails naming it
  std::string error;
  EXPECT_FALSE(FindDesignMetric("focal_stack_ssm", &error));
  EXPECT_NE(error.find("did you mean \"focal_stack_ssim\""), std::string::npos) << error;
}

#if LAYERLAB_WITH_EMBREE

TEST(DesignSearch, OneLayerFindsTheTargetsPlane) {
  // A grating on a plane at 1.3 D is reproduced exactly, up to its rendering, by one layer at 1.3 D only.
  const DesignSpec spec = ReadDesignSpec(ExamplePath("optimize/one_layer_depth.json"));
  DesignEvaluator evaluator(spec, Scratch("one_layer"));
  const DesignSearch search = SearchDesign(spec, &evaluator);
  const DesignEvaluation* best = BestFeasible(spec, evaluator);
  ASSERT_TRUE(best) << search.stopped;
  EXPECT_NEAR(best->x[0], 1.3, 0.01) << search.stopped;
  EXPECT_LE(evaluator.ran(), 25u);
}

TEST(DesignSearch, TheGlobalStagesFindTheOneLayerOptimum) {
  for (const char* global : {"mlsl", "crs"}) {
    DesignSpec spec = ReadDesignSpec(ExamplePath("optimize/one_layer_depth.json"));
    spec.optimizer.global = global;
    spec.optimizer.evaluations = 24;
    DesignEvaluator evaluator(spec, Scratch(std::string("global_") + global));
    const DesignSearch search = SearchDesign(spec, &evaluator);
    const DesignEvaluation* best = BestFeasible(spec, evaluator);
    ASSERT_TRUE(best) << global;
    EXPECT_NEAR(best->x[0], 1.3, 0.02) << global << ": " << search.stopped;
    EXPECT_LE(evaluator.ran(), 24u) << global;
  }
}

TEST(DesignSearch, TwoLayersMatchADenseGrid) {
  DesignSpec spec = ReadDesignSpec(ExamplePath("optimize/two_layer_depths.json"));
  // The local search as the example runs it, against every feasible point of a 0.3 D grid.
  spec.optimizer.evaluations = 40;
  DesignEvaluator grid(spec, Scratch("grid"));
  double grid_best = -INFINITY;
  std::vector<double> at;
  for (double front = 0.6; front <= 2.4 + 1e-9; front += 0.3)
    for (double rear = 0.2; rear <= 1.6 + 1e-9; rear += 0.3) {
      if (front - rear < 0.3) continue;
      const DesignEvaluation& e = grid.Evaluate({front, rear});
      ASSERT_FALSE(e.failed) << e.error;
      if (e.metrics[0] > grid_best) grid_best = e.metrics[0], at = e.x;
    }
  DesignEvaluator evaluator(spec, Scratch("two_layers"));
  const DesignSearch search = SearchDesign(spec, &evaluator);
  const DesignEvaluation* best = BestFeasible(spec, evaluator);
  ASSERT_TRUE(best) << search.stopped;
  EXPECT_GE(best->metrics[0], grid_best - 0.05)
      << "grid best " << grid_best << " dB at (" << at[0] << ", " << at[1] << ") D; found (" << best->x[0] << ", "
      << best->x[1] << ") D after " << evaluator.ran() << " evaluations: " << search.stopped;
  EXPECT_GE(best->x[0] - best->x[1], 0.3 - 1e-9);
  EXPECT_LE(evaluator.ran(), 40u);
  for (const DesignEvaluation* e : evaluator.evaluations()) EXPECT_FALSE(e->failed) << e->error;
}

TEST(DesignSearch, AResumedSearchRepeatsNoEvaluationAndEndsWhereAWholeOneEnds) {
  // Two variables, a linear constraint that the global stage crosses, and warm starts: what the
  // search decides from must be what it had asked so far, not the log's later entries.
  DesignSpec spec = ReadDesignSpec(ExamplePath("optimize/two_layer_depths.json"));
  spec.optimizer.global = "crs";
  spec.optimizer.evaluations = 10;
  const std::string whole_out = Scratch("whole");
  DesignEvaluator whole(spec, whole_out);
  SearchDesign(spec, &whole);
  ASSERT_EQ(whole.ran(), 10u);
  // What a kill after five evaluations leaves, with the fifth's jobs lost since: five log lines, a
  // sixth cut short, no jobs after the fourth. The fifth design runs again under its own id.
  const std::string out = Scratch("resume");
  fs::copy(whole_out, out, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  {
    std::ifstream in(whole_out + "/evaluations.jsonl");
    std::ofstream log(out + "/evaluations.jsonl", std::ios::trunc);
    std::string line;
    for (int i = 0; i < 5 && std::getline(in, line); ++i) log << line << "\n";
    log << "{\"index\": 5, \"id\": \"e0005\", \"x\": [1.9";
  }
  for (const DesignEvaluation* e : whole.evaluations())
    if (e->index >= 4) fs::remove_all(out + "/jobs/" + e->id);
  DesignEvaluator resumed(spec, out);
  EXPECT_EQ(resumed.Resume(), 4u);
  SearchDesign(spec, &resumed);
  EXPECT_EQ(resumed.replayed(), 4u);
  EXPECT_EQ(resumed.ran(), 6u);
  const auto a = resumed.evaluations(), b = whole.evaluations();
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i]->x, b[i]->x) << i;
    EXPECT_EQ(a[i]->warm_start, b[i]->warm_start) << i;
    EXPECT_EQ(a[i]->id, b[i]->id) << i;
  }
  // Every line of the log whole: one per evaluation, the fifth's twice (before and after its jobs were lost).
  std::ifstream log(out + "/evaluations.jsonl");
  size_t lines = 0;
  for (std::string line; std::getline(log, line); ++lines) {
    nlohmann::json entry;
    EXPECT_NO_THROW(entry = nlohmann::json::parse(line)) << line;
  }
  EXPECT_EQ(lines, 11u);
}

TEST(DesignGradient, MatchesCentralDifferencesOfConvergedSolves) {
  // The envelope theorem's gradient of the solve's PSNR with respect to both layers' depths, against
  // central differences: of the error at the solved patterns on the display compiled at x +- h (the
  // chain through the compile and the placement gradient), and of PSNR(x +- h) solved again
  // (warm-started from x, as the optimizer would). The solved patterns hold detail at the pixel scale,
  // so the error bends within a few hundredths of a pixel: the steps are small.
  DesignSpec spec = ReadDesignSpec(ExamplePath("optimize/two_layer_depths.json"));
  ASSERT_EQ(GradientProblem(spec), "");
  spec.base["solve"]["solver"] = "quasi-newton";  // converges in far fewer iterations than the multiplicative updates
  spec.iterations = 300;
  const std::string out = Scratch("gradient");
  DesignEvaluator evaluator(spec, out);
  const std::vector<double> x = {1.6, 0.8};
  const DesignEvaluation& at = evaluator.Evaluate(x);
  ASSERT_FALSE(at.failed) << at.error;
  const std::vector<double> exact = PsnrGradient(spec, evaluator, at);
  ASSERT_EQ(exact.size(), 2u);
  const std::string folder = JobFolder(out, evaluator.JobsOf(at).front());
  const LightField target = ReadLightField(folder + "/out/target/lightfield");
  const Patterns solved =
      ReadPatterns(DisplayModel(Compile(LoadScene(folder + "/scene.json")), target.geometry, Sampling::kBilinear),
                   folder + "/out/solve");
  auto fixed_psnr = [&](const std::vector<double>& y) {
    DesignEvaluation moved = at;
    moved.x = y;
    const SweepJob job = evaluator.JobsOf(moved).front();
    const DisplaySystem system =
        Compile(ParseScene(job.scene, JobFolder(out, job) + "/scene.json", ElementRegistry::WithBuiltins()));
    return PsnrDb(Objective(DisplayModel(system, target.geometry, Sampling::kBilinear), target, solved),
                  target.rgb.size());
  };
  ASSERT_NEAR(fixed_psnr(x), at.metrics[0], 1e-3) << "the target is not the one the solve saw (out of range?)";
  for (size_t v = 0; v < 2; ++v) {
    std::vector<double> up = x, down = x;
    up[v] += 1e-4;
    down[v] -= 1e-4;
    const double chain = (fixed_psnr(up) - fixed_psnr(down)) / 2e-4;
    EXPECT_NEAR(exact[v], chain, 0.03 * std::abs(chain)) << spec.variables[v].name << ": dB/D at fixed patterns";
    up[v] = x[v] + 2e-3;
    down[v] = x[v] - 2e-3;
    const double resolved = (evaluator.Evaluate(up).metrics[0] - evaluator.Evaluate(down).metrics[0]) / 4e-3;
    EXPECT_NEAR(exact[v], resolved, 0.15 * std::abs(resolved)) << spec.variables[v].name << ": dB/D solved again";
    EXPECT_GT(std::abs(resolved), 0.3) << "a slope too small to check against";
  }
}

TEST(DesignSearch, AGradientSearchFindsTheOneLayerOptimum) {
  nlohmann::json d = ReadExample("optimize/one_layer_depth.json");
  d["scene"] = ExamplePath("optimize/one_layer_small.json");
  d["optimizer"] = {{"local", "slsqp"}, {"evaluations", 20}};
  const std::string path = Scratch("slsqp_design") + "/design.json";
  std::ofstream(path) << d.dump(2);
  const DesignSpec spec = ReadDesignSpec(path);
  DesignEvaluator evaluator(spec, Scratch("slsqp"));
  const DesignSearch search = SearchDesign(spec, &evaluator);
  const DesignEvaluation* best = BestFeasible(spec, evaluator);
  ASSERT_TRUE(best) << search.stopped;
  EXPECT_NEAR(best->x[0], 1.3, 0.01) << search.stopped;
  EXPECT_LE(evaluator.ran(), 12u) << "COBYLA takes 18 evaluations on this problem";
}

TEST(DesignSearch, AMultistartsStartsAreIndependentOfTheirOrder) {
  // What lets the runners run the starts in parallel: a start's evaluations are the same whichever
  // starts ran before it, and the best over them all finds the one-layer optimum.
  DesignSpec spec = ReadDesignSpec(ExamplePath("optimize/one_layer_depth.json"));
  spec.optimizer.global = "multistart";
  spec.optimizer.starts = 3;
  spec.optimizer.evaluations = 21;
  const std::string forward = Scratch("starts_forward"), backward = Scratch("starts_backward");
  for (int k = 0; k < 3; ++k) RunStart(spec, forward, k);
  for (int k = 2; k >= 0; --k) RunStart(spec, backward, k);
  const MultistartRecord a(spec, forward), b(spec, backward);
  ASSERT_EQ(a.evaluations().size(), b.evaluations().size());
  EXPECT_LE(a.evaluations().size(), 21u);
  for (size_t i = 0; i < a.evaluations().size(); ++i) {
    EXPECT_EQ(a.evaluations()[i]->id, b.evaluations()[i]->id) << i;
    EXPECT_EQ(a.evaluations()[i]->x, b.evaluations()[i]->x) << i;
    EXPECT_EQ(a.evaluations()[i]->metrics, b.evaluations()[i]->metrics) << i;
    const DesignEvaluation& e = *a.evaluations()[i];
    if (!e.warm_start.empty()) {
      EXPECT_EQ(e.warm_start.substr(0, 4), e.start + "-") << "warm starts stay in a start";
    }
  }
  EXPECT_EQ(a.evaluations().front()->x, std::vector<double>{0.6});
  const DesignEvaluation* best = BestFeasible(spec, a.evaluations());
  ASSERT_TRUE(best);
  EXPECT_NEAR(best->x[0], 1.3, 0.01);
  // A start whose log is complete is replayed, not run again.
  const StartOutcome again = RunStart(spec, forward, 1);
  EXPECT_EQ(again.ran, 0u);
  EXPECT_EQ(again.replayed, again.asked);
}

#endif

}  // namespace
}  // namespace layerlab

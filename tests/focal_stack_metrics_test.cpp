// The focal stack's perceptual metrics in a solve's trace
// (SolverOptions::measure_metrics): the rows that measure them, and the last
// row's values against the mean over states of each state's score, the
// retinal images made here by the retinal operator from the solve's final
// patterns and the target.
#include <cmath>
#include <random>

#include "layerlab/kernels/synthesis.h"
#include "layerlab/metrics/retinal_metrics.h"
#include "layerlab/retina/retina.h"
#include "layerlab/retina/retinal_operator.h"
#include "layerlab/solvers/retinal_objective.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

TEST(FocalStackMetrics, TheyAreTheMeanOverStatesAtTheRowsThatMeasureThem) {
  const DisplaySystem system = testing::CompileJson(testing::ShrunkExample("multiplicative_2layer.json", 24, 12, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  Patterns truth = model.UniformPatterns(0.5f);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.2f, 0.9f);
  for (LayerPattern& p : truth)
    for (float& v : p.rgb) v = u(rng);
  const LightField target = Synthesize(model, truth);
  SolverOptions o = SolverRegistry::Builtins().get("multiplicative").defaults;
  o.iterations = 9;
  o.measure_focal_stack = true;
  o.measure_metrics = ParseRetinalMetrics("ssim,jnd", "metrics");
  o.metric_settings.fovea_deg = std::array<double, 2>{3.0, -2.0};  // weighted about a gaze, the JND pooled by RMS
  o.metric_settings.jnd_minkowski_exponent = 2;
  Patterns t;
  const SolverReport report = SolverRegistry::Builtins().create("multiplicative")->Solve(model, target, o, &t);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
  std::vector<int> measured;
  for (const IterationRecord& row : report.trace) {
    EXPECT_EQ(std::isnan(row.focal_stack_ssim), std::isnan(row.focal_stack_jnd)) << row.iteration;
    EXPECT_TRUE(std::isnan(row.focal_stack_ms_ssim));
    if (!std::isnan(row.focal_stack_ssim)) measured.push_back(row.iteration);
  }
  EXPECT_EQ(measured, (std::vector<int>{0, 1, 2, 3, 5, 8, 9}));
  // The states, grid and pupil the solve's focal stack uses; each state's images made here.
  const RetinalObjective objective(model, target, RetinalOptionsOf(o));
  std::vector<std::array<double, 3>> foci;
  for (double d : objective.states()) foci.push_back(ChannelAccommodation(system.eye, d));
  const RetinaGrid& grid = objective.retina();
  const RetinalOperator op(model.geometry(), model.projection(0).sampling(), grid, PupilSamples(system.eye), foci);
  std::vector<std::vector<float>> shown, seen;
  op.Apply(Synthesize(model, t), &shown);
  op.Apply(target, &seen);
  const MetricViewing viewing{
      grid.resolution_rad * 180 / std::acos(-1.0), model.white_luminance(), true, 3.0, -2.0, 2.0};
  double ssim = 0, jnd = 0;
  for (size_t a = 0; a < foci.size(); ++a) {
    const Image display{grid.cols, grid.rows, {"R", "G", "B"}, shown[a]},
        natural{grid.cols, grid.rows, {"R", "G", "B"}, seen[a]};
    ssim += o.measure_metrics[1]->score(display, natural, viewing) / foci.size();
    jnd += o.measure_metrics[2]->score(display, natural, viewing) / foci.size();
  }
  EXPECT_NEAR(report.trace.back().focal_stack_ssim, ssim, 1e-12);
  EXPECT_NEAR(report.trace.back().focal_stack_jnd, jnd, 1e-9 * jnd);
  EXPECT_GT(report.trace.back().focal_stack_ssim, report.trace.front().focal_stack_ssim);
}

TEST(FocalStackMetrics, TheyNeedTheFocalStackMeasured) {
  SolverOptions o;
  o.measure_metrics = ParseRetinalMetrics("jnd", "metrics");
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("measure_metrics"), std::string::npos) << error;
  o.measure_focal_stack = true;
  EXPECT_TRUE(o.IsValid(&error)) << error;
}

}  // namespace
}  // namespace layerlab

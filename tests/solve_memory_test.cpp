// The solve's workspace (kernels/solve_workspace.h) and the memory estimate
// built on its layout (solvers/memory_estimate.h): the layout against sizes
// by hand, the passes holding exactly what the layout says, and the estimate
// against the peak a solve reaches in a process of its own.
#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "layerlab/framework/lightfield_io.h"
#include "layerlab/kernels/joint_pass.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/retina/retina_workspace.h"
#include "layerlab/solvers/memory_estimate.h"
#include "layerlab/solvers/multiplicative_update.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/retinal_objective.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::CompileJson;
using testing::ShrunkExample;

Patterns RandomPatterns(const DisplayModel& model, uint64_t seed) {
  SolverOptions random;
  random.initial_value = -1;  // uniform in [0.25, 0.75]
  random.seed = seed;
  return InitialPatterns(model, random);
}

// The hybrid's passes (synthesis and one layer's update) on the paper's
// display, every branch on the one-tap path, summed by hand from what each
// buffer holds: per thread the column caches and resampled layers (each
// layer's rows x the rays' columns, 16-byte pixels), four ray rows, two
// views, one layer's column sums; shared the padded patterns, the view
// errors and two updates' double sums.
TEST(SolveWorkspace, LayoutOfTheHybridsPassesBySizesByHand) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 40, 20, 5));
  LightFieldGeometry g = DisplayLightFieldGeometry(system);
  g.cols = 32, g.rows = 24;  // rays unlike the layers' pixels
  const DisplayModel model(system, g);
  const int threads = 3;
  const double rows = 20, cols = g.cols, pixels = 40 * 20, views = 25, view = 32 * 24 * 3 * 4.0;
  const double per_thread =
      4 * rows * cols * 16 * 2 + 4 * cols * 16 + 2 * view + (rows * cols * 2 + pixels * 2) * 16 + rows;
  const double shared = 4 * pixels * 16 + views * 8 + 4 * pixels * 3 * 8;
  const WorkspaceLayout layout = SolveWorkspace::Layout(model, threads, kSynthesisPass | kLayerUpdatePass);
  EXPECT_EQ(double(layout.bytes()), per_thread * threads + shared);
  EXPECT_EQ(layout.threads, threads);
  // The joint pass adds every layer's column sums per thread, a ray row, and every layer's double sums.
  const WorkspaceLayout all = SolveWorkspace::Layout(model, threads, kAllPasses);
  EXPECT_EQ(double(all.bytes()) - double(layout.bytes()),
            (4 * ((rows * cols * 2 + pixels * 2) * 16 + rows) + cols * 16) * threads + 4 * pixels * 3 * 8 * 2);
}

// Every pass that takes a workspace, on the one-tap path and the general
// one (bilinear sampling): afterwards the workspace holds exactly what the
// layout said, so no pass grew a buffer beyond what the estimate counts.
TEST(SolveWorkspace, PassesHoldWhatTheLayoutSays) {
  for (Sampling sampling : {Sampling::kNearest, Sampling::kBilinear})
    for (const char* example : {"paper_prototype.json", "multiplicative_2layer.json"}) {
      const DisplaySystem system = CompileJson(ShrunkExample(example, 24, 12, 3));
      LightFieldGeometry g = DisplayLightFieldGeometry(system);
      g.cols = 20, g.rows = 14;
      const DisplayModel model(system, g, sampling);
      const Patterns truth = RandomPatterns(model, 3);
      const LightField target = Synthesize(model, truth);
      Patterns t = RandomPatterns(model, 4);
      const int threads = omp_get_max_threads();
      SolveWorkspace workspace(model, threads, kAllPasses);
      const size_t laid_out = SolveWorkspace::Layout(model, threads, kAllPasses).bytes();
      EXPECT_EQ(workspace.Bytes(), laid_out) << example;
      const BranchTarget whole = [&](size_t view, float*) { return target.view(view); };
      SolverOptions options;
      for (size_t b = 0; b < model.branch_count(); ++b)
        for (int layer : model.branch_layers(b))
          UpdateLayerMultiplicative(model, b, layer, whole, options, &t, &workspace);
      LayerUpdate kept = KeptLayerUpdate(&workspace);
      double error = 0;
      ComputeLayerUpdate(model, {0, model.branch_layers(0)[0]}, whole, t, &workspace, &kept, &error);
      const double objective = Objective(model, target, t, &workspace);
      EXPECT_NEAR(objective, Objective(model, target, t), 1e-9 * objective);  // a workspace of its own: the same
      JointPass pass(model, &workspace);
      EXPECT_NEAR(pass.Run(target, t), objective, 1e-5 * objective);
      LightField out(g);
      Synthesize(model, t, &out, &workspace);
      EXPECT_EQ(workspace.Bytes(), laid_out) << example << " " << ToString(sampling);
    }
}

// With the target at hand, a pass over its values tells whether the solve
// will make a clipped copy of it: counted then, not before.
TEST(SolveMemory, ClippedCopyCountedWhenTheTargetNeedsIt) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 24, 12, 3));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  LightField target = Synthesize(model, RandomPatterns(model, 6));
  auto without_program = [&](const MemoryEstimate& e) { return double(e.counted) - double(e.program); };
  const MemoryEstimate within = EstimateSolveMemory(model, "hybrid", 2, &target);
  EXPECT_FALSE(within.clipped_copy_counted);
  target.rgb[7] = 2.5f;  // above the two branches' sum in green
  const MemoryEstimate beyond = EstimateSolveMemory(model, "hybrid", 2, &target);
  EXPECT_TRUE(beyond.clipped_copy_counted);
  EXPECT_EQ(without_program(beyond) - without_program(within), double(target.rgb.size()) * 4);
  EXPECT_NE(beyond.breakdown.find(" + its clipped copy "), std::string::npos) << beyond.breakdown;
}

// The retinal objective's tables, counted before it is made
// (RetinalObjectiveBytes), are the bytes its operators hold once made.
TEST(SolveMemory, RetinalTablesCountedBeforeTheObjectiveIsMade) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 40, 20, 5));
  for (Sampling sampling : {Sampling::kNearest, Sampling::kBilinear}) {
    const DisplayModel model(system, DisplayLightFieldGeometry(system), sampling);
    const LightField target = Synthesize(model, RandomPatterns(model, 8));
    RetinalObjectiveOptions options;
    const RetinalObjective objective(model, target, options);
    EXPECT_EQ(RetinalObjectiveBytes(model, options, 2).tables, objective.TableBytes()) << ToString(sampling);
    options.pupils = {{0, 0, 1.0}, {0.7e-3, -0.3e-3, 1.0}};  // an eyebox's pupils: a set of tables each
    const RetinalObjective eyebox(model, target, options);
    EXPECT_EQ(RetinalObjectiveBytes(model, options, 2).tables, eyebox.TableBytes()) << ToString(sampling);
    EXPECT_GT(eyebox.TableBytes(), objective.TableBytes());
  }
}

// The estimate counts the retinal objective only when the solve makes it.
TEST(SolveMemory, RetinalObjectiveCountedWhenTheSolveMakesIt) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 40, 20, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  SolverOptions options = SolverRegistry::Builtins().get("quasi-newton").defaults;
  const MemoryEstimate light_field = EstimateSolveMemory(model, "quasi-newton", options, 2);
  options.objective = ObjectiveKind::kRetinal;
  const MemoryEstimate retinal = EstimateSolveMemory(model, "quasi-newton", options, 2);
  const RetinalObjectiveMemory parts = RetinalObjectiveBytes(model, options.retinal, 2);
  auto without_program = [&](const MemoryEstimate& e) { return double(e.counted) - double(e.program); };
  EXPECT_GE(without_program(retinal) - without_program(light_field), double(parts.kept()));
  EXPECT_NE(retinal.breakdown.find(" + the retinal objective "), std::string::npos) << retinal.breakdown;
  EXPECT_EQ(light_field.breakdown.find("retinal"), std::string::npos) << light_field.breakdown;
}

// The retina's workspace (retina/retina_workspace.h), on the display's one-tap
// path at one focus and at a focus per channel, and for a light field's
// rays under both samplings: sized before the first image, it holds what its
// layout says after images of several patterns, so no image grew a buffer;
// shared by a sweep's states, what the layout of the largest sizes says.
TEST(RetinaWorkspace, ImagesHoldWhatTheLayoutSays) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 24, 12, 3));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const RetinaGrid retina = MakeRetinaGrid(0.2, 0.1, 0.004);
  const std::vector<PupilPoint> pupil = PupilSamples(system.eye);
  const int threads = omp_get_max_threads();
  RetinaWorkspace shared;
  RetinaWorkspaceSizes largest;
  for (const std::array<double, 3>& focus :
       {std::array<double, 3>{1.0, 1.0, 1.0}, std::array<double, 3>{0.6, 1.0, 1.6}}) {
    const DisplayRetinaTables tables(model, retina, pupil, focus);
    const size_t laid_out = RetinaWorkspace::Layout(tables.workspace_sizes(), threads).bytes();
    EXPECT_GT(laid_out, 0u);
    for (uint64_t seed : {1, 2}) {
      RetinaOfDisplay(model, RandomPatterns(model, seed), tables);
      EXPECT_EQ(tables.workspace().Bytes(), laid_out) << focus[0];
      RetinaOfDisplay(model, RandomPatterns(model, seed), tables, &shared);
    }
    largest.column_tables = std::max(largest.column_tables, tables.workspace_sizes().column_tables);
    largest.ring = std::max(largest.ring, tables.workspace_sizes().ring);
  }
  EXPECT_EQ(shared.sizes().column_tables, largest.column_tables);
  EXPECT_EQ(shared.sizes().ring, largest.ring);
  EXPECT_EQ(shared.Bytes(), RetinaWorkspace::Layout(shared.sizes(), threads).bytes());
  const LightField lf = Synthesize(model, RandomPatterns(model, 3));
  const RetinaWorkspaceSizes sizes = LightFieldRetinaSizes(lf.geometry, retina, pupil);
  RetinaWorkspace workspace(sizes, threads);
  const size_t laid_out = RetinaWorkspace::Layout(sizes, threads).bytes();
  EXPECT_GT(laid_out, 0u);
  EXPECT_EQ(workspace.Bytes(), laid_out);
  for (Sampling sampling : {Sampling::kNearest, Sampling::kBilinear})
    for (double red : {1.0, 0.6}) RetinaOfLightField(lf, sampling, retina, pupil, {red, 1.0, 1.6}, &workspace);
  EXPECT_EQ(workspace.Bytes(), laid_out);
}

// A traced retinal target that is a light field's rays has its images made
// image-wise, in a retina workspace: the estimate counts that workspace's
// layout for the objective's grid and pupil, and one ray by ray holds none.
TEST(SolveMemory, RetinaWorkspaceCountedForATracedLightFieldTarget) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 40, 20, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = Synthesize(model, RandomPatterns(model, 8));
  SolverOptions options = SolverRegistry::Builtins().get("quasi-newton").defaults;
  options.objective = ObjectiveKind::kRetinal;
  options.retinal.target = RetinalTarget::kTraced;
  const SceneRadiance rays = LightFieldRadiance(target);
  options.retinal.target_radiance = [rays](const PupilPoint& u, double dx, double dy) { return rays(u, dx, dy); };
  EXPECT_EQ(RetinalObjectiveBytes(model, options.retinal, 2).retina_workspace, 0u);
  options.retinal.target_radiance = rays;
  const RetinalObjective objective(model, target, options.retinal);
  const size_t workspace =
      RetinaWorkspace::Layout(LightFieldRetinaSizes(target.geometry, objective.retina(), PupilSamples(system.eye)), 2)
          .bytes();
  const RetinalObjectiveMemory parts = RetinalObjectiveBytes(model, options.retinal, 2);
  EXPECT_GT(workspace, 0u);
  EXPECT_EQ(parts.retina_workspace, workspace);
  EXPECT_GE(parts.construction, workspace);
  const MemoryEstimate e = EstimateSolveMemory(model, "quasi-newton", options, 2);
  EXPECT_NE(e.breakdown.find("made in a workspace of " + FormatBytes(double(workspace))), std::string::npos)
      << e.breakdown;
}

// The estimate is printed ("the solve needs about 1.33 GB") as the bound
// itself: rounded up to the digits FormatBytes shows, not to the nearest.
TEST(SolveMemory, EstimatePrintedWithoutRoundingDown) {
  const DisplaySystem system = CompileJson(testing::ReadExample("paper_prototype.json"));
  for (int cols : {400, 800}) {
    LightFieldGeometry g = DisplayLightFieldGeometry(system);
    g.views_x = g.views_y = 13, g.cols = cols, g.rows = cols / 2;
    const MemoryEstimate e = EstimateSolveMemory(system, g, "hybrid", 2);
    const std::string printed = FormatBytes(double(e.bytes));
    const double value = std::stod(printed), scale = printed.find("GB") != std::string::npos ? 1e9 : 1e6;
    EXPECT_NEAR(value * scale, double(e.bytes), 1.0) << printed;
    EXPECT_GE(double(e.bytes), double(e.counted + e.margin)) << printed;
  }
}

// The child's side of the test below: the estimate before anything of
// light-field size exists, then the target (the dice, or one synthesized),
// a short solve, and the process's peak (VmHWM). The retinal case solves a
// smaller geometry with the retinal objective.
TEST(SolveMemory, DISABLED_ChildSolve) {
  const char* out = std::getenv("LAYERLAB_MEMORY_CHILD_OUT");
  if (!out) GTEST_SKIP() << "run by SolveMemory.*Peak*";
  const char* dice = std::getenv("LAYERLAB_MEMORY_CHILD_DICE");
  const char* solver_env = std::getenv("LAYERLAB_MEMORY_CHILD_SOLVER");
  const std::string solver = solver_env ? solver_env : "hybrid";
  SolverOptions options = SolverRegistry::Builtins().get(solver).defaults;
  const bool retinal = std::getenv("LAYERLAB_MEMORY_CHILD_RETINAL") != nullptr;
  if (retinal) options.objective = ObjectiveKind::kRetinal;
  const DisplaySystem system = CompileJson(testing::ReadExample("paper_prototype.json"));
  LightFieldGeometry g = dice ? ReadLightFieldGeometry(dice) : DisplayLightFieldGeometry(system);
  if (!dice) g.views_x = g.views_y = 7, g.cols = 200, g.rows = 100;
  if (retinal) g.views_x = g.views_y = 5, g.cols = 120, g.rows = 60;
  const DisplayModel model(system, g);
  const MemoryEstimate estimate = EstimateSolveMemory(model, solver, options, omp_get_max_threads());
  const LightField target =
      dice ? ReadLightField(dice, {.load_depth = false}) : Synthesize(model, RandomPatterns(model, 5));
  // quasi-newton: the warm start's iterations, then steps.
  options.iterations = solver == "hybrid" ? 2 : options.warm_start_iterations + 2;
  Patterns t;
  const SolverReport report = SolverRegistry::Builtins().create(solver)->Solve(model, target, options, &t);
  ASSERT_TRUE(report.IsSolutionUsable()) << report.FullReport();
  ASSERT_EQ(report.out_of_range, 0u);  // no clipped copy, as the estimate assumed
  size_t peak_kb = 0;
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) peak_kb = std::stoul(line.substr(6));
  std::ofstream(out) << estimate.bytes << " " << peak_kb * 1024 << "\n" << estimate.breakdown << "\n";
}

// AddressSanitizer's shadow memory and quarantine are part of the peak (the
// sanitizer build's 110 MB against 84 MB estimated on the synthetic target).
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

// How far above the peak the estimate may be and still be useful: its
// margin (kMemoryMarginFraction and kMemoryMarginBytes) and the set-up's
// transient parts counted at once (docs/performance.md, memory).
constexpr double kEstimateAbovePeakAtMost = 0.10;

// The estimate is an upper bound of the peak, and not far above it.
void ExpectEstimateBoundsPeak(const std::string& dice, const std::string& solver, bool retinal = false) {
  if (kAddressSanitizer) GTEST_SKIP() << "the peak under AddressSanitizer includes its shadow memory";
  char self[4096];
  const ssize_t length = ::readlink("/proc/self/exe", self, sizeof self - 1);
  ASSERT_GT(length, 0);
  self[length] = 0;
  const std::string out =
      (std::filesystem::temp_directory_path() / ("solve_memory_" + std::to_string(::getpid()))).string();
  std::string command = "LAYERLAB_MEMORY_CHILD_OUT='" + out + "' ";
  if (!dice.empty()) command += "LAYERLAB_MEMORY_CHILD_DICE='" + dice + "' ";
  if (retinal) command += "LAYERLAB_MEMORY_CHILD_RETINAL=1 ";
  command += "LAYERLAB_MEMORY_CHILD_SOLVER='" + solver + "' ";
  command += "'" + std::string(self) +
             "' --gtest_also_run_disabled_tests --gtest_filter=SolveMemory.DISABLED_ChildSolve > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::ifstream in(out);
  double estimate = 0, peak = 0;
  std::string breakdown;
  in >> estimate >> peak;
  std::getline(in >> std::ws, breakdown);
  std::filesystem::remove(out);
  ASSERT_GT(peak, 0);
  EXPECT_LE(peak, estimate) << "the peak exceeds the estimate: " << breakdown;
  EXPECT_LE(estimate, (1 + kEstimateAbovePeakAtMost) * peak) << breakdown;
  std::printf("estimate %.1f MB, peak %.1f MB (%+.1f %%): %s\n", estimate / 1e6, peak / 1e6,
              100 * (estimate - peak) / peak, breakdown.c_str());
}

std::string Dice() {
  const std::string folder = std::string(LAYERLAB_DATA_DIR) + "/dice";
  return std::filesystem::exists(folder + "/lightfield.json") ? folder : "";
}

TEST(SolveMemory, EstimateBoundsThePeakOnASyntheticTarget) { ExpectEstimateBoundsPeak("", "hybrid"); }

// Quasi-newton holds the warm start's chase, then its vectors in its place.
TEST(SolveMemory, QuasiNewtonEstimateBoundsThePeakOnASyntheticTarget) { ExpectEstimateBoundsPeak("", "quasi-newton"); }

// The retinal objective's operator tables, retinal images and pass.
TEST(SolveMemory, RetinalObjectiveEstimateBoundsThePeak) { ExpectEstimateBoundsPeak("", "quasi-newton", true); }

TEST(SolveMemory, EstimateBoundsThePeakOnTheDice) {
  if (Dice().empty()) GTEST_SKIP() << "no " << LAYERLAB_DATA_DIR << "/dice";
  ExpectEstimateBoundsPeak(Dice(), "hybrid");
}

TEST(SolveMemory, QuasiNewtonEstimateBoundsThePeakOnTheDice) {
  if (Dice().empty()) GTEST_SKIP() << "no " << LAYERLAB_DATA_DIR << "/dice";
  ExpectEstimateBoundsPeak(Dice(), "quasi-newton");
}

}  // namespace
}  // namespace layerlab

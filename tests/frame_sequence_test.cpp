// A moving target solved frame by frame (analysis/frame_sequence.h), against the same frames rendered and
// solved here one by one: frame 0 cold, each later frame from the one before, the cold references, and each
// layer's change between frames.
#include <cmath>
#include <fstream>
#include <string>

#include "layerlab/analysis/frame_sequence.h"
#include "layerlab/framework/error.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/compile.h"
#include "layerlab/targets/target_renderer.h"
#include "layerlab/tests/render_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

SolverReport SolveOnce(const SolveJob& job, const DisplayModel& model, const LightField& lf, int iterations,
                       const Patterns* from, Patterns* out) {
  SolverOptions o = job.config.options;
  if (iterations > 0) o.iterations = iterations;
  o.initial_patterns = from;
  return SolverRegistry::Builtins().create(job.config.solver)->Solve(model, lf, o, out);
}

// The reduced example's display and its scene's solve settings.
struct SmallJob {
  Scene scene = LoadScene(testing::ExamplePath("small/hybrid_small.json"));
  DisplaySystem system = Compile(scene);
  SolveJob job;
  SmallJob() {
    job.system = &system;
    job.config = SolveJobConfig(scene, system);
  }
};

TEST(FrameSequence, EachFrameGoesOnFromTheFrameBefore) {
  const SmallJob small;
  const DisplaySystem& system = small.system;
  const SolveJob& job = small.job;
  const TargetScene moving = LoadTarget(testing::ExamplePath("small/small_dice_turning.json"));
  FrameSequenceOptions options;
  options.frames = 3;
  options.frame_iterations = 2;
  options.cold_every = 2;
  int called = 0;
  const FrameSequence sequence = SolveFrameSequence(job, moving, options, [&](const FrameRow&) { ++called; });
  ASSERT_EQ(sequence.rows.size(), 3u);
  EXPECT_EQ(called, 3);
  ASSERT_EQ(sequence.layer_names.size(), system.layers.size());

  std::vector<LightField> frames;
  for (int f = 0; f < 3; ++f) {
    EXPECT_EQ(sequence.rows[f].time_s, f / 30.0);
    frames.push_back(RenderTarget(TargetSceneAt(moving, f / 30.0)));
  }
  const DisplayModel model(system, frames[0].geometry, job.config.sampling);
  Patterns p0, p1, p2, cold2;
  const SolverReport r0 = SolveOnce(job, model, frames[0], 0, nullptr, &p0);
  const SolverReport r1 = SolveOnce(job, model, frames[1], 2, &p0, &p1);
  const SolverReport r2 = SolveOnce(job, model, frames[2], 2, &p1, &p2);
  const SolverReport c2 = SolveOnce(job, model, frames[2], 0, nullptr, &cold2);
  EXPECT_EQ(sequence.rows[0].iterations, job.config.options.iterations);
  EXPECT_EQ(sequence.rows[0].psnr_db, r0.final_psnr_db);
  EXPECT_EQ(sequence.rows[0].cold_psnr_db, r0.final_psnr_db);
  EXPECT_EQ(sequence.rows[1].iterations, 2);
  EXPECT_EQ(sequence.rows[1].psnr_db, r1.final_psnr_db);
  EXPECT_TRUE(std::isnan(sequence.rows[1].cold_psnr_db)) << "frame 1 is not a multiple of --cold-every";
  EXPECT_EQ(sequence.rows[2].psnr_db, r2.final_psnr_db);
  EXPECT_EQ(sequence.rows[2].cold_psnr_db, c2.final_psnr_db);
  for (size_t k = 0; k < p1.size(); ++k) {
    double sum = 0;
    for (size_t i = 0; i < p1[k].rgb.size(); ++i) sum += std::pow(double(p1[k].rgb[i]) - p0[k].rgb[i], 2);
    EXPECT_NEAR(sequence.rows[1].layer_change[k], std::sqrt(sum / p1[k].rgb.size()), 1e-12) << k;
    EXPECT_GT(sequence.rows[1].layer_change[k], 0) << k;
    EXPECT_EQ(sequence.rows[0].layer_change[k], 0) << k;
  }
  ASSERT_EQ(sequence.last.patterns.size(), p2.size());
  for (size_t k = 0; k < p2.size(); ++k) EXPECT_EQ(sequence.last.patterns[k].rgb, p2[k].rgb) << k;

  const std::string csv = testing::ScratchDir() + "/frames.csv";
  WriteFramesCsv(sequence, csv);
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("frame,time_s,render_s,solve_s,iterations,psnr_db,cold_psnr_db,cold_solve_s,", 0), 0u);
  EXPECT_NE(header.find(",change_" + sequence.layer_names[0]), std::string::npos);
  int lines = 0;
  while (std::getline(in, line)) ++lines;
  EXPECT_EQ(lines, 3);
  EXPECT_NE(FramesSummary(sequence, options, moving).find("over 1 frame compared"), std::string::npos)
      << FramesSummary(sequence, options, moving);
}

TEST(FrameSequence, AStillSceneIsRefused) {
  const SmallJob small;
  const SolveJob& job = small.job;
  const TargetScene still = LoadTarget(testing::ExamplePath("small/small_dice_target.json"));
  FrameSequenceOptions options;
  options.frames = 2;
  try {
    SolveFrameSequence(job, still, options);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not move"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace layerlab

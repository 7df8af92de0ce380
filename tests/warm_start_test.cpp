// A warm start (SolverOptions::initial_patterns): a solve begun from given
// patterns goes on from them, so two halves make the whole (the hybrid's too).
#include <gtest/gtest.h>

#include <string>

#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

// The multiplicative solver's iteration is a function of the patterns alone,
// so three iterations begun from three iterations' patterns are six.
TEST(WarmStart, ASolveGoesOnFromThePatternsItIsGiven) {
  const DisplaySystem system = testing::CompileJson(testing::ShrunkExample("multiplicative_2layer.json", 32, 16, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  Patterns truth = model.UniformPatterns(0);
  for (size_t k = 0; k < truth.size(); ++k)
    for (size_t i = 0; i < truth[k].rgb.size(); ++i)
      truth[k].rgb[i] = 0.2f + 0.7f * float((i * 2654435761u + 97 * k) % 1000) / 1000;
  const LightField target = Synthesize(model, truth);
  auto solve = [&](const std::string& solver, int iterations, const Patterns* from, Patterns* out) {
    SolverOptions o;
    o.iterations = iterations;
    o.initial_patterns = from;
    return SolverRegistry::Builtins().create(solver)->Solve(model, target, o, out);
  };
  Patterns whole, half, rest;
  solve("multiplicative", 6, nullptr, &whole);
  solve("multiplicative", 3, nullptr, &half);
  const SolverReport r = solve("multiplicative", 3, &half, &rest);
  ASSERT_EQ(rest.size(), whole.size());
  for (size_t k = 0; k < whole.size(); ++k) EXPECT_EQ(rest[k].rgb, whole[k].rgb) << "layer " << k;
  // Every solver starts from them: its trace's first row is their objective.
  for (const std::string solver : {"hybrid", "joint", "quasi-newton", "multiplicative"}) {
    Patterns out;
    const SolverReport warm = solve(solver, 1, &half, &out);
    EXPECT_EQ(warm.trace.front().objective, Objective(model, target, half)) << solver;
  }
  // Patterns of another display are refused.
  Patterns wrong = half;
  wrong.pop_back();
  Patterns out;
  bool refused = false;
  try {
    refused = !solve("multiplicative", 1, &wrong, &out).IsSolutionUsable();
  } catch (const Error& e) {
    refused = std::string(e.what()).find("warm start") != std::string::npos;
  }
  EXPECT_TRUE(refused);
}

// The hybrid's chase is each set's share of the target until the sets have emitted light of their own
// (the paper's first iteration); patterns given to begin from have, so a solve begun from three iterations'
// patterns goes on as the whole solve does, and one begun from a converged solution stays converged.
TEST(WarmStart, TheHybridGoesOnChasingWhatTheOtherSetsEmit) {
  const DisplaySystem system = testing::CompileJson(testing::ShrunkExample("paper_prototype.json", 24, 12, 3));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  ASSERT_EQ(model.branch_count(), 2u);
  Patterns truth = model.UniformPatterns(0);
  for (size_t k = 0; k < truth.size(); ++k)
    for (size_t i = 0; i < truth[k].rgb.size(); ++i)
      truth[k].rgb[i] = 0.2f + 0.7f * float((i * 2654435761u + 97 * k) % 1000) / 1000;
  const LightField target = Synthesize(model, truth);
  auto solve = [&](int iterations, const Patterns* from, Patterns* out) {
    SolverOptions o;
    o.iterations = iterations;
    o.initial_patterns = from;
    return SolverRegistry::Builtins().create("hybrid")->Solve(model, target, o, out);
  };
  Patterns whole, half, rest;
  const SolverReport w = solve(6, nullptr, &whole);
  solve(3, nullptr, &half);
  const SolverReport r = solve(3, &half, &rest);
  ASSERT_EQ(w.trace.size(), 7u);
  ASSERT_EQ(r.trace.size(), 4u);
  for (int i = 1; i <= 3; ++i)
    EXPECT_NEAR(r.trace[i].objective, w.trace[3 + i].objective, 1e-9 * w.trace[3 + i].objective) << "iteration " << i;
  Patterns on;
  const SolverReport more = solve(1, &whole, &on);
  EXPECT_LE(more.final_objective, w.final_objective);
}

}  // namespace
}  // namespace layerlab

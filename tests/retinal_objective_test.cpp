// The retinal operator A_a (retina/retinal_operator.h) against the retina
// command's general path (ray by ray through the pupil), its transpose
// against <A x, y> = <x, A^T y>, and the retinal objective
// (solvers/retinal_objective.h, retinal_pass.h): its gradient against
// central differences, its pinhole one-state case against the light-field
// objective of the centre view, a recovered known focal stack, and the
// objective over an eyebox of pupils against its single pupils' objectives.
#include <omp.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include "layerlab/eye/contrast_sensitivity.h"
#include "layerlab/eye/spectral_filter.h"
#include "layerlab/framework/fixed_order_sum.h"
#include "layerlab/framework/units.h"
#include "layerlab/kernels/joint_pass.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retinal_operator.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/retinal_objective.h"
#include "layerlab/solvers/retinal_pass.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::CompileJson;
using testing::ErrorOf;
using testing::RandomLightField;
using testing::RandomPatterns;
using testing::ShrunkExample;

LightFieldGeometry Geometry(int cols, int rows, int views) { return testing::WindowGeometry(cols, rows, views); }

// A 4 mm pupil of 5 x 5 points, some with a wavefront slope.
std::vector<PupilPoint> Pupil() {
  EyeModel eye;
  eye.pupil_samples_x = eye.pupil_samples_y = 5;
  std::vector<PupilPoint> pupil = PupilSamples(eye);
  for (size_t p = 0; p < pupil.size(); p += 3) pupil[p].slope_x = 2e-4 * double(p % 5), pupil[p].slope_y = -1e-4;
  return pupil;
}

struct Case {
  Sampling sampling;
  std::array<double, 3> focus;
  const char* name;
};
const Case kCases[] = {{Sampling::kNearest, {1.0, 1.0, 1.0}, "nearest"},
                       {Sampling::kBilinear, {0.4, 0.4, 0.4}, "bilinear"},
                       {Sampling::kNearest, {2.1, 2.5, 2.9}, "nearest, a focus per channel"},
                       {Sampling::kBilinear, {0.0, 0.3, 0.6}, "bilinear, a focus per channel"}};

RetinaGrid Grid() {
  RetinaGrid grid = MakeRetinaGrid(11 * kRadiansPerDegree, 7 * kRadiansPerDegree,
                                   0.23 * kRadiansPerDegree);  // a little past the window
  grid.center_x_rad = 0.2 * kRadiansPerDegree;
  return grid;
}

TEST(RetinalOperator, IsTheRetinaRayByRayThroughThePupil) {
  const LightFieldGeometry g = Geometry(60, 36, 7);
  const LightField lf = RandomLightField(g, 3);
  const RetinaGrid grid = Grid();
  const std::vector<PupilPoint> pupil = Pupil();
  for (const Case& c : kCases) {
    const RetinalOperator a(g, c.sampling, grid, pupil, c.focus);
    std::vector<float> image;
    a.Apply(lf, &image);
    const Image brute = RetinaOfSceneRayByRay(LightFieldRadiance(lf, c.sampling), grid, pupil, c.focus);
    ASSERT_EQ(image.size(), brute.pixels.size());
    double largest = 0;
    for (size_t k = 0; k < image.size(); ++k) largest = std::max(largest, std::abs(double(image[k]) - brute.pixels[k]));
    EXPECT_LT(largest, 2e-6) << c.name;
    // Not all dark: most retinal samples see the window.
    const size_t lit = size_t(std::count_if(image.begin(), image.end(), [](float v) { return v > 0; }));
    EXPECT_GT(lit, image.size() / 2) << c.name;
  }
  // Several states in one operator (the pupil's view blends shared): each state as alone.
  for (Sampling sampling : {Sampling::kNearest, Sampling::kBilinear}) {
    std::vector<std::array<double, 3>> states;
    for (const Case& c : kCases) states.push_back(c.focus);
    const RetinalOperator all(g, sampling, grid, pupil, states);
    std::vector<std::vector<float>> images;
    all.Apply(lf, &images);
    ASSERT_EQ(images.size(), states.size());
    for (size_t a = 0; a < states.size(); ++a) {
      std::vector<float> alone;
      RetinalOperator(g, sampling, grid, pupil, states[a]).Apply(lf, &alone);
      EXPECT_EQ(images[a], alone) << "state " << a;
    }
  }
}

template <class A, class B>
double Dot(const A& a, const B& b) {
  double sum = 0;
  for (size_t k = 0; k < a.size(); ++k) sum += double(a[k]) * b[k];
  return sum;
}

TEST(RetinalOperator, TransposeIsTheAdjoint) {
  const LightFieldGeometry g = Geometry(60, 36, 7);
  const RetinaGrid grid = Grid();
  const std::vector<PupilPoint> pupil = Pupil();
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(0, 1);
  for (const Case& c : kCases) {
    const RetinalOperator a(g, c.sampling, grid, pupil, c.focus);
    const LightField x = RandomLightField(g, 17);
    std::vector<float> y(a.retinal_values()), ax;
    for (float& v : y) v = u(rng);
    a.Apply(x, &ax);
    LightField aty(g);
    std::fill(aty.rgb.begin(), aty.rgb.end(), 7.0f);  // overwritten
    a.ApplyTranspose(y, &aty);
    const double left = Dot(ax, y), right = Dot(x.rgb, aty.rgb);
    EXPECT_NEAR(left, right, 1e-6 * std::abs(left)) << c.name;
    // Accumulating adds A^T y once more.
    a.ApplyTranspose(y, &aty, true);
    EXPECT_NEAR(Dot(x.rgb, aty.rgb), 2 * right, 1e-6 * std::abs(left)) << c.name;
  }
  // Several states: sum_a <A_a x, y_a> = <x, sum_a A_a^T y_a>.
  std::vector<std::array<double, 3>> states;
  for (const Case& c : kCases) states.push_back(c.focus);
  const RetinalOperator all(g, Sampling::kBilinear, grid, pupil, states);
  const LightField x = RandomLightField(g, 23);
  std::vector<std::vector<float>> y(states.size(), std::vector<float>(all.retinal_values())), ax;
  for (auto& image : y)
    for (float& v : image) v = u(rng);
  all.Apply(x, &ax);
  double left = 0;
  for (size_t a = 0; a < states.size(); ++a) left += Dot(ax[a], y[a]);
  LightField aty(g);
  all.ApplyTranspose(y, &aty);
  EXPECT_NEAR(left, Dot(x.rgb, aty.rgb), 1e-6 * left);
}

// The displays of the solver tests, each layer kind and flip: the paper's
// hybrid (its reflected branch flipped by the beam splitter) as compiled,
// with every flip toggled, bilinear, and rotated (the general path); the two
// 2-layer displays; a time-multiplexed 3-layer display (its subframes are branches).
struct Display {
  std::string name;
  DisplaySystem system;
  Sampling sampling = Sampling::kNearest;
};
std::vector<Display> Displays() {
  std::vector<Display> d;
  const DisplaySystem hybrid = CompileJson(ShrunkExample("paper_prototype.json", 24, 12, 5));
  d.push_back({"hybrid", hybrid});
  DisplaySystem flipped = hybrid;
  for (VirtualLayer& layer : flipped.layers) layer.flip_x = !layer.flip_x, layer.flip_y = !layer.flip_y;
  d.push_back({"hybrid, flips toggled", flipped});
  d.push_back({"hybrid, bilinear", hybrid, Sampling::kBilinear});
  DisplaySystem rotated = hybrid;
  for (VirtualLayer& layer : rotated.layers) layer.rotation_rad = 1e-12;
  d.push_back({"hybrid, rotated", rotated});
  d.push_back({"multiplicative", CompileJson(ShrunkExample("multiplicative_2layer.json", 24, 12, 5))});
  d.push_back({"additive", CompileJson(ShrunkExample("additive_2layer.json", 24, 12, 5))});
  nlohmann::json subframes = ShrunkExample("tensor_display_rank3.json", 24, 12, 5);
  subframes["subframes"] = 2;
  d.push_back({"3-layer tensor, 2 subframes", CompileJson(subframes)});
  return d;
}

RetinalObjectiveOptions FewStates() {
  RetinalObjectiveOptions o;
  o.states_diopters = {0.3, 1.1, 2.2};
  o.weights = {1.0, 0.5, 2.0};
  return o;
}

// Through the display: the linearization J of L(t) (exact, L is affine in
// each layer: J d = sum_k L(t with t_k + d_k) - L(t)) and J^T from the
// joint pass (against the target L - v its sums give den - num = J^T v), so
// <A_a J d, y> = <d, J^T A_a^T y> for each layer kind and flip.
TEST(RetinalOperator, AdjointThroughEveryLayerKindAndFlip) {
  for (const Display& d : Displays()) {
    const DisplayModel model(d.system, DisplayLightFieldGeometry(d.system), d.sampling);
    const LightFieldGeometry& g = model.geometry();
    const RetinalObjective objective(model, LightField(g), FewStates());
    const EyeModel& eye = d.system.eye;
    const RetinalOperator a(g, d.sampling, objective.retina(), PupilSamples(eye), ChannelAccommodation(eye, 1.1));
    const Patterns t = RandomPatterns(model, 4, 0.2f, 0.9f);
    const Patterns delta = RandomPatterns(model, 5, 0.0f, 1.0f);
    const LightField base = Synthesize(model, t);
    LightField jd(g);
    for (size_t k = 0; k < t.size(); ++k) {
      Patterns moved = t;
      for (size_t i = 0; i < moved[k].rgb.size(); ++i) moved[k].rgb[i] += delta[k].rgb[i];
      const LightField l = Synthesize(model, moved);
      for (size_t i = 0; i < jd.rgb.size(); ++i) jd.rgb[i] += l.rgb[i] - base.rgb[i];
    }
    std::vector<float> y(a.retinal_values()), ajd;
    std::mt19937 rng(6);
    std::uniform_real_distribution<float> u(0, 1);
    for (float& v : y) v = u(rng);
    a.Apply(jd, &ajd);
    LightField v(g);
    a.ApplyTranspose(y, &v);
    LightField effective = base;
    for (size_t i = 0; i < v.rgb.size(); ++i) effective.rgb[i] -= v.rgb[i];
    JointPass pass(model);
    pass.Run(effective, t);
    double right = 0;
    for (size_t k = 0; k < t.size(); ++k)
      for (size_t i = 0; i < t[k].rgb.size(); ++i) right += double(delta[k].rgb[i]) * pass.residual()[k][i];
    const double left = Dot(ajd, y);
    EXPECT_GT(left, 0) << d.name;
    // J d and J^T v in float: a few float roundings per value.
    EXPECT_NEAR(left, right, 1e-5 * std::abs(left)) << d.name;
  }
}

// The retinal pass's gradient (2 res times its scale) against
// central differences of the objective at `trials` values of each layer.
void ExpectGradientMatchesCentralDifferences(const DisplayModel& model, const LightField& target,
                                             const RetinalObjective& objective, const Patterns& t, int trials,
                                             const std::string& name) {
  RetinalPass pass(model, target, objective);
  const double scaled = pass.Run(t);
  const double f = objective.Evaluate(Synthesize(model, t));
  EXPECT_NEAR(scaled * pass.scale(), f, 1e-9 * f) << name;
  const std::vector<std::vector<double>> res = pass.sums().residual();
  std::mt19937 rng(5);
  for (size_t k = 0; k < t.size(); ++k)
    for (int trial = 0; trial < trials; ++trial) {
      const size_t i = std::uniform_int_distribution<size_t>(0, t[k].rgb.size() - 1)(rng);
      const double gradient = 2.0 * res[k][i] * pass.scale();
      const float h = 1e-2f;
      Patterns plus = t, minus = t;
      plus[k].rgb[i] += h;
      minus[k].rgb[i] -= h;
      // f is quadratic in one value (L is affine in it): central differences are exact up to round-off.
      const double difference =
          (objective.Evaluate(Synthesize(model, plus)) - objective.Evaluate(Synthesize(model, minus))) / (2 * h);
      // Float images: f to about 1e-6 relative, the difference to 1e-6 f / h.
      EXPECT_NEAR(gradient, difference, 2e-3 * std::abs(difference) + 1e-6 * f / h)
          << name << ", layer " << k << ", value " << i;
    }
}

// Over an eyebox of pupils the objective is the pupils' weighted sum of the
// single-pupil objectives, each made separately from a scene whose eye sits
// at that pupil position: its value, each state's error and its adjoint
// (half the gradient in the light field).
TEST(EyeboxObjective, IsThePupilsWeightedSumOfSingleEyeObjectives) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 24, 12, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = Synthesize(model, RandomPatterns(model, 8, 0.1f, 1.0f));
  const LightField x = Synthesize(model, RandomPatterns(model, 9, 0.0f, 1.0f));
  RetinalObjectiveOptions o = FewStates();
  o.pupils = {{0, 0, 1.0}, {0.6e-3, 0, 3.0}, {0, -0.4e-3, 2.0}, {0.3e-3, 0.3e-3, 0.0}};
  const RetinalObjective eyebox(model, target, o);
  ASSERT_EQ(eyebox.pupil_count(), 3u);  // the one of weight 0 adds nothing and has no operator
  std::vector<double> per_state;
  LightField adjoint(model.geometry());
  const double f = eyebox.EvaluateWithAdjoint(x, &per_state, &adjoint);

  double expected = 0;
  std::vector<double> expected_states(3, 0.0);
  std::vector<double> expected_adjoint(adjoint.rgb.size(), 0.0);
  const double share[] = {1.0 / 6, 3.0 / 6, 2.0 / 6};
  for (size_t p = 0; p < 3; ++p) {
    DisplaySystem moved = system;
    moved.eye.pose.pupil_offset_m = {o.pupils[p].offset_x_m, o.pupils[p].offset_y_m};
    const DisplayModel moved_model(moved, DisplayLightFieldGeometry(moved));
    ASSERT_EQ(moved_model.geometry().ray_count(), model.geometry().ray_count());
    const RetinalObjective single(moved_model, target, FewStates());
    std::vector<double> states;
    LightField m(model.geometry());
    expected += share[p] * single.EvaluateWithAdjoint(x, &states, &m);
    for (size_t a = 0; a < 3; ++a) expected_states[a] += share[p] * states[a];
    for (size_t i = 0; i < m.rgb.size(); ++i) expected_adjoint[i] += share[p] * m.rgb[i];
  }
  EXPECT_GT(f, 0);
  EXPECT_NEAR(f, expected, 1e-6 * expected);
  for (size_t a = 0; a < 3; ++a) EXPECT_NEAR(per_state[a], expected_states[a], 1e-6 * expected_states[a]) << a;
  double largest = 0, scale = 0;
  for (size_t i = 0; i < adjoint.rgb.size(); ++i) {
    largest = std::max(largest, std::abs(adjoint.rgb[i] - expected_adjoint[i]));
    scale = std::max(scale, std::abs(expected_adjoint[i]));
  }
  EXPECT_GT(scale, 0);
  EXPECT_LT(largest, 1e-5 * scale);
}

// The pupils' sum is still the objective's derivative (central differences),
// with a Gaussian-weighted 3 x 3 grid.
TEST(EyeboxObjective, GradientMatchesCentralDifferences) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 24, 12, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = Synthesize(model, RandomPatterns(model, 8, 0.1f, 1.0f));
  SolverOptions solve;
  solve.objective = ObjectiveKind::kRetinal;
  solve.retinal = FewStates();
  solve.eyebox_range_m = 0.5e-3, solve.eyebox_sigma_m = 0.5e-3;
  const RetinalObjective objective(model, target, RetinalOptionsOf(solve));
  ASSERT_EQ(objective.pupil_count(), 9u);
  ExpectGradientMatchesCentralDifferences(model, target, objective, RandomPatterns(model, 11, 0.2f, 0.9f), 3, "eyebox");
}

// The grid by hand: (2 n + 1)^2 positions n = range / step apart, row by row
// from the lowest y; Gaussian weights exp(-r^2 / 2 sigma^2), scaled to sum to
// 1 by the objective, whose pupil samples sit at each position.
TEST(EyeboxObjective, TheGridAndItsWeights) {
  SolverOptions o;
  o.objective = ObjectiveKind::kRetinal;
  EXPECT_TRUE(EyeboxPupils(o).empty());
  o.eyebox_range_m = 1e-3;
  std::vector<PupilWeight> grid = EyeboxPupils(o);
  ASSERT_EQ(grid.size(), 9u);
  EXPECT_EQ(grid.front().offset_x_m, -1e-3);
  EXPECT_EQ(grid.front().offset_y_m, -1e-3);
  EXPECT_EQ(grid[5].offset_x_m, 1e-3);
  EXPECT_EQ(grid[5].offset_y_m, 0);
  for (const PupilWeight& p : grid) EXPECT_EQ(p.weight, 1);
  o.eyebox_step_m = 0.5e-3, o.eyebox_sigma_m = 0.8e-3;
  grid = EyeboxPupils(o);
  ASSERT_EQ(grid.size(), 25u);
  EXPECT_EQ(grid[12].offset_x_m, 0);
  EXPECT_NEAR(grid[0].weight / grid[12].weight, std::exp(-2.0 / (2 * 0.64)), 1e-14);
  EXPECT_NEAR(grid[13].weight / grid[12].weight, std::exp(-0.25 / (2 * 0.64)), 1e-14);

  EyeModel eye;
  eye.pose.pupil_offset_m = {0.2e-3, 0};
  RetinalObjectiveOptions r = RetinalOptionsOf(o);
  std::vector<double> weights;
  const std::vector<std::vector<PupilPoint>> pupils = RetinalPupils(eye, r, &weights);
  ASSERT_EQ(pupils.size(), 25u);
  double sum = 0, centre_x = 0;
  for (double w : weights) sum += w;
  EXPECT_NEAR(sum, 1, 1e-15);
  const std::vector<PupilPoint> own = PupilSamples(eye);
  ASSERT_EQ(pupils[0].size(), own.size());
  for (size_t i = 0; i < own.size(); ++i) {
    EXPECT_NEAR(pupils[0][i].x_m, own[i].x_m - 1e-3, 1e-15);
    EXPECT_NEAR(pupils[0][i].y_m, own[i].y_m - 1e-3, 1e-15);
    centre_x += pupils[0][i].center_x_m;
  }
  EXPECT_NEAR(centre_x / double(own.size()), -0.8e-3, 1e-15);
}

TEST(EyeboxObjective, BadGridsAndWeightsAreRefused) {
  SolverOptions o;
  o.eyebox_range_m = 1e-3;
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("eyebox_range: weighs pupil positions in the retinal objective"), std::string::npos) << error;
  o.objective = ObjectiveKind::kRetinal;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.eyebox_step_m = 2e-3;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_EQ(error, "eyebox_step: 0.002: must be at most eyebox_range (0.001)");
  o.eyebox_step_m = 0.2e-3;  // 11 x 11
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_EQ(error,
            "eyebox_step: 0.0002: makes a grid of 121 pupil positions, more than 81 (each holds its own "
            "retinal tables)");
  EXPECT_EQ(ErrorOf([&] { EyeboxPupils(o); }), "eyebox_step: makes more than 81 pupil positions");
  o.eyebox_step_m = 0.25e-3;  // 9 x 9
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.eyebox_range_m = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_EQ(error, "eyebox_step: describes the eyebox grid of eyebox_range, which is 0 (the eye's pupil alone)");
  o.eyebox_range_m = 0.02;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("eyebox_range: 0.02: must be in [0, 0.01]"), std::string::npos) << error;

  EyeModel eye;
  RetinalObjectiveOptions r;
  r.pupils = {{0, 0, 0.0}, {1e-3, 0, 0.0}};
  EXPECT_EQ(ErrorOf([&] { RetinalPupils(eye, r); }), "the retinal objective's pupil positions all have weight 0");
  r.pupils[1].weight = -1;
  EXPECT_EQ(ErrorOf([&] { RetinalPupils(eye, r); }),
            "a pupil position's weight in the retinal objective must be finite and >= 0");
}

// The objective, each state's error and the light field's error have the
// same bits on any thread count (their long sums run in a fixed order), so a
// retinal solve does too.
TEST(RetinalObjective, TheSameBitsOnAnyThreadCount) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 48, 24, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = Synthesize(model, RandomPatterns(model, 8, 0.1f, 1.0f));
  const Patterns t = RandomPatterns(model, 9, 0.0f, 1.0f);
  ASSERT_GT(target.rgb.size(), 2 * kFixedOrderSumChunk);
  const int threads = omp_get_max_threads();
  std::vector<RetinalMeasures> measures;
  std::vector<std::vector<double>> states;
  for (int n : {1, 2, 3, 4}) {
    omp_set_num_threads(n);
    const RetinalObjective objective(model, target, FewStates());
    measures.push_back(MeasureRetinalObjective(target, objective, Synthesize(model, t)));
    states.emplace_back();
    objective.Evaluate(Synthesize(model, t), &states.back());
  }
  omp_set_num_threads(threads);
  for (size_t k = 1; k < measures.size(); ++k) {
    EXPECT_EQ(measures[k].objective, measures[0].objective) << k + 1 << " threads";
    EXPECT_EQ(measures[k].light_field_objective, measures[0].light_field_objective) << k + 1 << " threads";
    EXPECT_EQ(states[k], states[0]) << k + 1 << " threads";
  }
}

TEST(RetinalObjective, GradientMatchesCentralDifferences) {
  for (const Display& d : Displays()) {
    const DisplayModel model(d.system, DisplayLightFieldGeometry(d.system), d.sampling);
    const LightField target = Synthesize(model, RandomPatterns(model, 8, 0.1f, 1.0f));
    const RetinalObjective objective(model, target, FewStates());
    ExpectGradientMatchesCentralDifferences(model, target, objective, RandomPatterns(model, 11, 0.2f, 0.9f), 5, d.name);
  }
}

// A pinhole pupil is one point at the eyebox centre, which with an odd view
// count is the centre view's position: its rays read that view alone. One
// state: the ray of retinal sample j crosses the origin plane at
// z tan(angle_j), angle_j = (j + 0.5 - cols / 2) atan(pixel / z); over a
// 10 deg window of 40 pixels that lies within 0.05 pixel of pixel j's centre
// (tan(20 atan(p)) - 20 p = 0.0002 m/m against p = 0.0044), so with nearest
// sampling sample j reads pixel j, whatever the focus: f = the centre view's
// ||L - l||^2.
TEST(RetinalObjective, PinholeOneStateIsTheCentreViewsLightFieldObjective) {
  DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 24, 12, 5));
  system.eye.pupil_diameter_m = 0;
  const LightFieldGeometry g = Geometry(40, 24, 5);
  const DisplayModel model(system, g);
  const LightField target = Synthesize(model, RandomPatterns(model, 8, 0.1f, 1.0f));
  for (double state : {0.0, 1.7}) {
    RetinalObjectiveOptions o;
    o.states_diopters = {state};
    const RetinalObjective objective(model, target, o);
    ASSERT_EQ(objective.retina().cols, g.cols);
    const LightField l = Synthesize(model, RandomPatterns(model, 12, 0.0f, 1.0f));
    const size_t centre = g.view_index(g.views_y / 2, g.views_x / 2);
    double centre_view = 0;
    for (size_t k = 0; k < g.pixels_per_view() * 3; ++k) {
      const double e = double(l.view(centre)[k]) - target.view(centre)[k];
      centre_view += e * e;
    }
    EXPECT_NEAR(objective.Evaluate(l), centre_view, 1e-6 * centre_view) << state << " D";
  }
}

// The target is a display's own light field: its patterns make the target's
// focal stack exactly, and the retinal objective finds patterns that do.
TEST(RetinalObjective, SolversRecoverAKnownFocalStack) {
  for (const char* solver : {"quasi-newton", "joint"}) {
    const DisplaySystem system = CompileJson(ShrunkExample("multiplicative_2layer.json", 24, 12, 5));
    const DisplayModel model(system, DisplayLightFieldGeometry(system));
    const LightField target = Synthesize(model, RandomPatterns(model, 8, 0.3f, 0.9f));
    SolverOptions o = SolverRegistry::Builtins().find(solver)->defaults;
    o.objective = ObjectiveKind::kRetinal;
    o.retinal = FewStates();
    o.iterations = 400;
    Patterns t;
    const SolverReport r = SolverRegistry::Builtins().create(solver)->Solve(model, target, o, &t);
    ASSERT_TRUE(r.IsSolutionUsable()) << r.FullReport();
    const IterationRecord& last = r.trace.back();
    RecordProperty(std::string(solver) + "_focal_stack_psnr_db", std::to_string(last.focal_stack_psnr_db));
    RecordProperty(std::string(solver) + "_iterations", std::to_string(r.iterations));
    EXPECT_GT(last.focal_stack_psnr_db, 60.0) << solver << "\n" << r.FullReport();
    // The trace's objective is the retinal one of the patterns returned, and it never rose.
    const RetinalObjective objective(model, target, o.retinal);
    EXPECT_NEAR(objective.Evaluate(Synthesize(model, t)), last.objective, 1e-3 * last.objective + 1e-12);
    // (From the quasi-Newton steps on: the warm start's hybrid steps lower the light-field objective.)
    for (size_t k = size_t(o.warm_start_iterations) + 1; k < r.trace.size(); ++k)
      EXPECT_LE(r.trace[k].objective, r.trace[k - 1].objective * (1 + 1e-9)) << solver << ", iteration " << k;
    EXPECT_NEAR(last.psnr_db, PsnrDb(Objective(model, target, t), model.geometry().ray_count() * 3), 1e-3);
  }
}

// A traced target: the target images are the scene seen through the pupil.
// A uniform radiance c is c on every retinal sample at every state, so with
// x = 0 the objective is sum_a w_a c^2 (samples per state), by hand.
TEST(RetinalObjective, TracedTargetOfAUniformSceneIsItsRadianceEverywhere) {
  const DisplaySystem system = CompileJson(ShrunkExample("multiplicative_2layer.json", 24, 12, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  RetinalObjectiveOptions o = FewStates();
  o.target = RetinalTarget::kTraced;
  const float c = 0.37f;
  o.target_radiance = [c](const PupilPoint&, double, double) { return Rgb{c, c, c}; };
  const RetinalObjective objective(model, LightField(model.geometry()), o);
  double expected = 0;
  for (double w : o.weights) expected += w * double(c) * c * double(objective.samples_per_state());
  std::vector<double> per_state;
  EXPECT_NEAR(objective.Evaluate(LightField(model.geometry()), &per_state), expected, 1e-6 * expected);
  for (double e : per_state) EXPECT_NEAR(e, double(c) * c * double(objective.samples_per_state()), 1e-6 * e);
}

// Traced from the target light field's own radiance, ray by ray (a plain
// function, so not the image-wise path), the target images are A_a l: the
// objective is the default one's, to float rounding.
TEST(RetinalObjective, TracedTargetOfTheLightFieldsOwnRaysIsTheDefault) {
  for (Sampling sampling : {Sampling::kNearest, Sampling::kBilinear}) {
    const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 24, 12, 5));
    const DisplayModel model(system, DisplayLightFieldGeometry(system), sampling);
    const LightField target = Synthesize(model, RandomPatterns(model, 8, 0.1f, 1.0f));
    const RetinalObjective by_operator(model, target, FewStates());
    RetinalObjectiveOptions o = FewStates();
    o.target = RetinalTarget::kTraced;
    const SceneRadiance rays = LightFieldRadiance(target, sampling);
    o.target_radiance = [rays](const PupilPoint& u, double dx, double dy) { return rays(u, dx, dy); };
    const RetinalObjective traced(model, LightField(model.geometry()), o);
    const LightField x = Synthesize(model, RandomPatterns(model, 9, 0.0f, 1.0f));
    const double f = by_operator.Evaluate(x);
    EXPECT_GT(f, 0);
    EXPECT_NEAR(traced.Evaluate(x), f, 1e-5 * f) << (sampling == Sampling::kNearest ? "nearest" : "bilinear");
  }
}

TEST(RetinalObjective, TracedTargetWithoutASceneIsRefused) {
  const DisplaySystem system = CompileJson(ShrunkExample("multiplicative_2layer.json", 24, 12, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  RetinalObjectiveOptions o = FewStates();
  o.target = RetinalTarget::kTraced;
  EXPECT_EQ(ErrorOf([&] { RetinalObjective(model, LightField(model.geometry()), o); }),
            "the retinal objective's traced target needs a target scene (target_scene), not a light field");
}

// Mannos and Sakrison's model, its values worked independently (SciPy's
// bounded minimizer and Brent's root finder on the same formula).
TEST(ContrastSensitivity, IsMannosSakrisonBeyondItsPeakAndOneBelow) {
  EXPECT_NEAR(ContrastSensitivityPeak(), 7.890914518525334, 1e-6);
  EXPECT_EQ(ContrastSensitivityWeight(0), 1);
  EXPECT_EQ(ContrastSensitivityWeight(5), 1);
  EXPECT_NEAR(ContrastSensitivityWeight(12), 0.8963369788962496, 1e-9);
  EXPECT_NEAR(ContrastSensitivityWeight(30), 0.19062863677054534, 1e-9);
  EXPECT_NEAR(ContrastSensitivityWeight(20.283280701757413), 0.5, 1e-9);
  EXPECT_NEAR(ContrastSensitivityWeight(35.722651085531595), 0.1, 1e-9);
}

// A periodic cosine is an eigenvector of every even gain: filtered, it is
// the cosine times the gain at its frequency.
TEST(SpectralFilter, ACosineIsScaledByTheGainAtItsFrequency) {
  const int nx = 40, ny = 24;
  const double spacing = 0.5, fx = 3.0 / (nx * spacing), fy = 2.0 / (ny * spacing);
  std::vector<std::complex<double>> field(size_t(nx) * ny);
  auto cosine = [&](int i, int j) { return std::cos(2 * std::numbers::pi * (fx * j * spacing + fy * i * spacing)); };
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < nx; ++j) field[size_t(i) * nx + j] = 0.25 + cosine(i, j);
  auto gain = [](double u, double v) { return 1 / (1 + u * u + 3 * v * v); };
  FilterPeriodic(&field, nx, ny, spacing, gain);
  double largest = 0;
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < nx; ++j)
      largest = std::max(largest, std::abs(field[size_t(i) * nx + j] - (0.25 + gain(fx, fy) * cosine(i, j))));
  EXPECT_LT(largest, 1e-12);
}

// With the weighting the objective's gradient is still its derivative
// (central differences), and on a retinal grid fine enough to resolve
// frequencies past the peak the weighting lowers the objective.
TEST(RetinalObjective, ContrastSensitivityGradientMatchesCentralDifferences) {
  const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 24, 12, 5));
  const DisplayModel model(system, DisplayLightFieldGeometry(system));
  const LightField target = Synthesize(model, RandomPatterns(model, 8, 0.1f, 1.0f));
  RetinalObjectiveOptions plain = FewStates();
  plain.resolution_rad = 0.02 * kRadiansPerDegree;  // 25 cpd at Nyquist
  RetinalObjectiveOptions weighted = plain;
  weighted.contrast_sensitivity = true;
  const RetinalObjective objective(model, target, weighted), unweighted(model, target, plain);
  Patterns t = RandomPatterns(model, 11, 0.2f, 0.9f);
  const LightField l = Synthesize(model, t);
  std::vector<double> per_state, per_state_plain;
  const double f = objective.Evaluate(l, &per_state), f_plain = unweighted.Evaluate(l, &per_state_plain);
  EXPECT_LT(f, 0.99 * f_plain);
  EXPECT_GT(f, 0.1 * f_plain);
  EXPECT_EQ(per_state, per_state_plain);  // the focal-stack PSNR stays the unweighted one
  ExpectGradientMatchesCentralDifferences(model, target, objective, t, 4, "contrast sensitivity");
}

}  // namespace
}  // namespace layerlab

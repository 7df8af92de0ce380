// The paper-scale workloads, each against its target on this machine
// (docs/performance.md), and the straightforward formulation the paper used
// (explicit sparse projection matrices) timed in the same run.
//
//   build/layerlab_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//   build/layerlab_bench --smoke      # seconds: reduced scale, for CI
//
// Counters: target_s is the target for the row, vs_target the
// measured time over it (below 1 meets it), peak_rss_MB the process's peak
// so far (benchmarks run in the order below, the sparse ones last).
#include <benchmark/benchmark.h>
#include <omp.h>

#include <unistd.h>
#include <Eigen/Sparse>
#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "layerlab/analysis/contrast.h"
#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/bench/bench_setup.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/framework/units.h"
#include "layerlab/kernels/joint_pass.h"
#include "layerlab/kernels/pair_lattice.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/retina/eye_optics.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/retina/retinal_operator.h"
#include "layerlab/solvers/additive_gram.h"
#include "layerlab/solvers/multiplicative_update.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/retinal_objective.h"
#include "layerlab/solvers/retinal_pass.h"
#include "layerlab/solvers/solve_config.h"
#include "layerlab/solvers/solver.h"

namespace layerlab::bench {
namespace {

template <class F>
double Timed(benchmark::State& state, F f) {
  auto start = std::chrono::steady_clock::now();
  f();
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state.SetIterationTime(seconds);
  return seconds;
}

void Report(benchmark::State& state, double target_seconds, double measured_seconds) {
  state.counters["target_s"] = target_seconds;
  state.counters["vs_target"] = measured_seconds / target_seconds;
  state.counters["peak_rss_MB"] = PeakRssMb();
}

// One solve of `iterations`; the time of the last iteration alone (the trace's
// difference: the first iteration also pays for first-touch allocations), or
// of the whole solve, is what the benchmark reports.
SolverReport RunSolver(const Workload& w, const std::string& solver, SolverOptions options) {
  Patterns t;
  return SolverRegistry::Builtins().create(solver)->Solve(*w.model, w.target, options, &t);
}

void BM_Synthesis(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  Patterns t = w.model->UniformPatterns(0.5f);
  LightField out(w.target.geometry);
  SolveWorkspace workspace(*w.model, omp_get_max_threads(), kSynthesisPass);
  for (auto _ : state) {
    Synthesize(*w.model, t, &out, &workspace);
    benchmark::DoNotOptimize(out.rgb.data());
  }
  state.counters["rays_per_s"] =
      benchmark::Counter(double(w.target.geometry.ray_count()), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["peak_rss_MB"] = PeakRssMb();
  state.SetLabel(w.target_name);
}

// The machine's floor for a pass: read the 162 MB target once on both
// threads (four-float vector sums, nothing else), and copy it once (read
// and write, as the hybrid's pass for the other set's light does).
void BM_MemoryFloorRead(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  const auto& l = w.target.rgb;
  const size_t n = l.size() / 4;
  for (auto _ : state) {
    using V = float __attribute__((vector_size(16)));
    float total = 0;
#pragma omp parallel reduction(+ : total)
    {
      V sum[4] = {};
#pragma omp for
      for (size_t k = 0; k < n; ++k) {
        V v;
        std::memcpy(&v, &l[k * 4], sizeof v);
        sum[k & 3] += v;
      }
      for (const V& v : sum) total += v[0] + v[1] + v[2] + v[3];
    }
    benchmark::DoNotOptimize(total);
  }
  state.counters["GB_per_s"] =
      benchmark::Counter(double(l.size()) * 4e-9, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_MemoryFloorCopy(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  const auto& l = w.target.rgb;
  std::vector<float> out(l.size());
  for (auto _ : state) {
#pragma omp parallel for
    for (size_t k = 0; k < l.size(); ++k) out[k] = l[k];
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["GB_per_s"] =
      benchmark::Counter(double(l.size()) * 8e-9, benchmark::Counter::kIsIterationInvariantRate);
}

// The passes an iteration is made of: one multiplicative update of one layer
// (layer 0 of the first branch, chasing the whole target) and one objective
// (a synthesis and the squared error). ns_per_ray is per ray of the light
// field, both threads together.
void BM_UpdatePass(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  Patterns t = w.model->UniformPatterns(0.5f);
  const LightField& l = w.target;
  BranchTarget whole = [&](size_t view, float*) { return l.view(view); };
  SolverOptions o;
  SolveWorkspace workspace(*w.model, omp_get_max_threads(), kLayerUpdatePass);  // as a solve holds it
  for (auto _ : state) UpdateLayerMultiplicative(*w.model, 0, w.model->branch_layers(0)[0], whole, o, &t, &workspace);
  state.counters["ns_per_ray"] =
      benchmark::Counter(double(l.geometry.ray_count()) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(w.target_name);
}

// The same update's sums from the target binned by pixel pair
// (kernels/pair_lattice.h; the hybrid's sets make their updates after the
// first so), and the binning itself, made once per set and iteration.
// Arg 0: the paper prototype's first set; 1: the 2-layer multiplicative display.
const Workload& PairLatticeWorkload(const benchmark::State& state) {
  return GetWorkload(state.range(0) == 0 ? "paper_prototype" : "multiplicative_2layer");
}

void BM_PairLatticeUpdate(benchmark::State& state) {
  const Workload& w = PairLatticeWorkload(state);
  Patterns t = w.model->UniformPatterns(0.5f);
  const PairLattice lattice(*w.model, 0);
  PairCells binned;
  lattice.Bin(w.target, &binned);
  std::vector<double> num(w.model->projection(lattice.layer_a()).pixel_count() * 3), den(num.size());
  PaddedLayers padded;
  padded.PadAll(t);
  const Rgb4* other = padded.pixels(lattice.layer_b());
  for (auto _ : state) lattice.UpdateSums(lattice.layer_a(), other, binned, num.data(), den.data());
  state.counters["rays_per_cell"] = lattice.rays() / double(lattice.cells());
  state.SetLabel(w.target_name);
}

void BM_PairLatticeBin(benchmark::State& state) {
  const Workload& w = PairLatticeWorkload(state);
  const PairLattice lattice(*w.model, 0);
  PairCells binned;
  for (auto _ : state) lattice.Bin(w.target, &binned);
  state.counters["rays_per_cell"] = lattice.rays() / double(lattice.cells());
  state.counters["ns_per_ray"] =
      benchmark::Counter(double(w.target.geometry.ray_count()) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(w.target_name);
}

void BM_ObjectivePass(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  Patterns t = w.model->UniformPatterns(0.5f);
  SolveWorkspace workspace(*w.model, omp_get_max_threads(), kSynthesisPass);
  for (auto _ : state) benchmark::DoNotOptimize(Objective(*w.model, w.target, t, &workspace));
  state.counters["ns_per_ray"] =
      benchmark::Counter(double(w.target.geometry.ray_count()) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(w.target_name);
}

// The pass of the solvers that move every layer at once (joint,
// quasi-newton): the objective and every layer's two sums.
void BM_JointPass(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  Patterns t = w.model->UniformPatterns(0.5f);
  JointPass pass(*w.model);
  for (auto _ : state) benchmark::DoNotOptimize(pass.Run(w.target, t));
  state.counters["ns_per_ray"] =
      benchmark::Counter(double(w.target.geometry.ray_count()) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(w.target_name);
}

// The time of the third iteration of a solve of three (the first two warm
// the caches); `budget` seconds is the figure the iteration should stay under.
void OneIteration(benchmark::State& state, const std::string& workload, const std::string& solver, double budget,
                  const std::string& label) {
  const Workload& w = GetWorkload(workload);
  SolverOptions o = SolverRegistry::Builtins().get(solver).defaults;
  o.iterations = 3;
  double last = 0;
  for (auto _ : state) {
    SolverReport r = RunSolver(w, solver, o);
    last = r.trace.back().seconds - r.trace[r.trace.size() - 2].seconds;
    state.SetIterationTime(last);
  }
  Report(state, budget, last);
  state.SetLabel(w.target_name + ", " + label);
}

// One quasi-newton iteration under the retinal objective (14 states, 0 to
// 2.6 D, through the paper's eye of 9 x 9 pupil samples) and one under the
// light-field objective, alternating in one run: the median iteration of a
// solve of `kSolveIterations` each (iterations 2 on: the first also pays for
// first touches), no warm start, so that a line search's extra evaluations
// count as often as they happen; ratio is retinal over light field
// (docs/retinal-objective.md; the goal is at most 3).
double MedianIterationSeconds(const SolverReport& r) {
  std::vector<double> step;
  for (size_t k = 2; k < r.trace.size(); ++k) step.push_back(r.trace[k].seconds - r.trace[k - 1].seconds);
  std::sort(step.begin(), step.end());
  return step.empty() ? 0 : step[step.size() / 2];
}

void BM_RetinalObjectiveIteration(benchmark::State& state) {
  constexpr int kSolveIterations = 8;
  const Workload& w = GetWorkload("paper_prototype");
  SolverOptions o = SolverRegistry::Builtins().get("quasi-newton").defaults;
  o.iterations = kSolveIterations;
  o.warm_start_iterations = 0;
  SolverOptions retinal = o;
  retinal.objective = ObjectiveKind::kRetinal;
  double light_field_s = 0, retinal_s = 0;
  for (auto _ : state) {
    light_field_s = MedianIterationSeconds(RunSolver(w, "quasi-newton", o));
    retinal_s = MedianIterationSeconds(RunSolver(w, "quasi-newton", retinal));
    state.SetIterationTime(retinal_s);
  }
  state.counters["light_field_s"] = light_field_s;
  state.counters["retinal_s"] = retinal_s;
  state.counters["ratio"] = retinal_s / light_field_s;
  state.counters["states"] = double(RetinalStates(w.model->system().eye, {}).size());
  state.counters["pupil_points"] = double(PupilSamples(w.model->system().eye).size());
  Report(state, 3 * light_field_s, retinal_s);
  state.SetLabel(w.target_name + ", quasi-newton");
}

// The gradient evaluation each objective's iteration is built on, at the same
// patterns, alternating: the retinal pass (synthesis, every state's A_a and
// A_a^T, the joint pass against the effective target) against the joint pass
// of the light-field objective; ratio is retinal over light field.
void BM_RetinalPass(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  const RetinalObjective objective(*w.model, w.target, {});
  RetinalPass retinal(*w.model, w.target, objective);
  JointPass light_field(*w.model);
  const Patterns t = w.model->UniformPatterns(0.5f);
  retinal.Run(t), light_field.Run(w.target, t);  // first touches
  double light_field_s = 0, retinal_s = 0;
  for (auto _ : state) {
    light_field_s = Timed(state, [&] { benchmark::DoNotOptimize(light_field.Run(w.target, t)); });
    retinal_s = Timed(state, [&] { benchmark::DoNotOptimize(retinal.Run(t)); });
    state.SetIterationTime(retinal_s);
  }
  state.counters["light_field_s"] = light_field_s;
  state.counters["retinal_s"] = retinal_s;
  state.counters["ratio"] = retinal_s / light_field_s;
  state.counters["peak_rss_MB"] = PeakRssMb();
  state.SetLabel(w.target_name);
}

// The retinal operator of that objective alone on the dice: A = every
// state's A_a applied to the target, and A^T = their transposes applied to
// those images (seconds per apply, the last of the run).
void BM_RetinalOperator(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  const EyeModel& eye = w.model->system().eye;
  const RetinalObjective objective(*w.model, w.target, {});
  std::vector<std::array<double, 3>> foci;
  for (double d : objective.states()) foci.push_back(ChannelAccommodation(eye, d));
  const RetinalOperator a(w.model->geometry(), w.model->projection(0).sampling(), objective.retina(), PupilSamples(eye),
                          foci);
  std::vector<std::vector<float>> images;
  LightField back(w.target.geometry);
  double apply_s = 0, transpose_s = 0;
  for (auto _ : state) {
    auto start = std::chrono::steady_clock::now();
    a.Apply(w.target, &images);
    auto middle = std::chrono::steady_clock::now();
    a.ApplyTranspose(images, &back);
    auto end = std::chrono::steady_clock::now();
    apply_s = std::chrono::duration<double>(middle - start).count();
    transpose_s = std::chrono::duration<double>(end - middle).count();
    state.SetIterationTime(apply_s + transpose_s);
  }
  state.counters["apply_s"] = apply_s;
  state.counters["transpose_s"] = transpose_s;
  state.counters["states"] = double(foci.size());
  state.counters["peak_rss_MB"] = PeakRssMb();
  state.SetLabel(w.target_name);
}

void BM_HybridIteration(benchmark::State& state) {
  OneIteration(state, "paper_prototype", "hybrid", 0.15, "2 sets x 3 sub-iterations");
}

// The same iteration behind a real N-BK7 singlet (examples/paper_prototype_la1608.json):
// each layer read through its exact ray map per channel (the general path) against
// the ideal magnifier's affine one-tap path above; the goal is at most 2 x.
void BM_HybridIterationRealLens(benchmark::State& state) {
  OneIteration(state, "paper_prototype_la1608", "hybrid", 0.3, "2 sets x 3 sub-iterations, real lens");
}

void BM_HybridSchedule(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  SolverOptions o = SolverRegistry::Builtins().find("hybrid")->defaults;  // 30 x 3
  SolverReport r;
  for (auto _ : state) {
    r = RunSolver(w, "hybrid", o);
    state.SetIterationTime(r.seconds);
  }
  state.counters["psnr_dB"] = r.final_psnr_db;
  Report(state, 5.0, r.seconds);
  state.SetLabel(w.target_name + ", 30 x 3");
}

// Beyond the paper: the seconds quasi-newton takes to the PSNR the hybrid's
// 30 x 3 schedule ends at, both run here (speedup = hybrid's seconds / these).
void BM_QuasiNewtonToHybridSchedulePsnr(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  const SolverReport hybrid = RunSolver(w, "hybrid", SolverRegistry::Builtins().find("hybrid")->defaults);
  SolverOptions o = SolverRegistry::Builtins().find("quasi-newton")->defaults;
  o.iterations = 1000;
  o.time_budget = hybrid.seconds;
  double reached = hybrid.seconds;
  for (auto _ : state) {
    const SolverReport r = RunSolver(w, "quasi-newton", o);
    const auto first = std::find_if(r.trace.begin(), r.trace.end(),
                                    [&](const IterationRecord& it) { return it.psnr_db >= hybrid.final_psnr_db; });
    reached = first == r.trace.end() ? r.seconds : first->seconds;
    state.SetIterationTime(reached);
  }
  state.counters["hybrid_s"] = hybrid.seconds;
  state.counters["psnr_dB"] = hybrid.final_psnr_db;
  state.counters["speedup"] = hybrid.seconds / reached;
  state.counters["peak_rss_MB"] = PeakRssMb();
  state.SetLabel(w.target_name);
}

void BM_MultiplicativeIteration(benchmark::State& state) {
  OneIteration(state, "multiplicative_2layer", "multiplicative", 0.025, "2 layers");
}

// A rank-K iteration of the 2-layer multiplicative display shown in K
// subframes against a rank-1 iteration, interleaved: each round times the
// last of three iterations at K = 1, then at K (multiplicative: K > 1 is the
// rank-K update, one joint pass per depth; quasi-newton: its steps alone,
// no warm start, one pass each unless the line search halves). The issue's
// target: per_K_vs_rank1 = t_K / (K t_1) at most 1.2.
void BM_RankKIteration(benchmark::State& state) {
  const std::string solver = state.range(0) == 0 ? "multiplicative" : "quasi-newton";
  const int k = static_cast<int>(state.range(1));
  const Workload& one = GetWorkload("multiplicative_2layer");
  const Workload& rank_k = GetWorkload("multiplicative_2layer", k);
  if (!Settings().smoke && rank_k.target_name != "dice") {
    state.SkipWithError("no dice target in " LAYERLAB_DATA_DIR "/dice: the rank-K rows are measured on it");
    return;
  }
  SolverOptions o = SolverRegistry::Builtins().get(solver).defaults;
  o.iterations = 3;
  o.tolerance = 0;
  o.warm_start_iterations = 0;
  auto last_iteration = [&](const Workload& w) {
    const SolverReport r = RunSolver(w, solver, o);
    return r.trace.back().seconds - r.trace[r.trace.size() - 2].seconds;
  };
  std::vector<double> t1, tk;
  for (auto _ : state) {
    t1.push_back(last_iteration(one));
    tk.push_back(last_iteration(rank_k));
    state.SetIterationTime(tk.back());
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  const double per_k = median(tk) / (k * median(t1));
  state.counters["rank1_ms"] = 1e3 * median(t1);
  state.counters["rankK_ms"] = 1e3 * median(tk);
  state.counters["per_K_vs_rank1"] = per_k;
  state.counters["target_per_K"] = 1.2;
  state.counters["peak_rss_MB"] = PeakRssMb();
  state.SetLabel(rank_k.target_name + ", " + solver + ", K = " + std::to_string(k));
}

void BM_AdditiveToConvergence(benchmark::State& state) {
  const Workload& w = GetWorkload("additive_2layer");
  SolverOptions o = SolverRegistry::Builtins().find("additive-trust-region")->defaults;
  o.tolerance = 1e-6;
  o.iterations = 1000;
  SolverReport r;
  for (auto _ : state) {
    r = RunSolver(w, "additive-trust-region", o);
    state.SetIterationTime(r.seconds);
  }
  state.counters["iterations"] = r.iterations;
  state.counters["psnr_dB"] = r.final_psnr_db;
  Report(state, 5.0, r.seconds);
  state.SetLabel(w.target_name + ", " + ToString(r.termination));
}

// One product with the additive display's normal matrix (solvers/additive_gram.h),
// the step the layer-space trust region repeats (a few per CG step).
void BM_AdditiveGramApply(benchmark::State& state) {
  const Workload& w = GetWorkload("additive_2layer");
  const AdditiveGram gram(*w.model);
  LayerVectors x, out;
  for (size_t k = 0; k < w.model->layer_count(); ++k) {
    x.emplace_back(w.model->projection(k).pixel_count() * 3);
    for (size_t i = 0; i < x.back().size(); ++i) x.back()[i] = double((i * 2654435761u) % 1000) / 1000;
  }
  for (auto _ : state) {
    gram.Apply(x, &out);
    benchmark::DoNotOptimize(out.front().data());
  }
  state.counters["peak_rss_MB"] = PeakRssMb();
  state.SetLabel(w.target_name + ", 2 layers");
}

// The display's retinal image on `grid` at one focus (uniform patterns of 0.5),
// as a focal stack makes each state's (analysis/retina_sweep.cpp): the
// state's tables made, the workspace the states share.
void DisplayRetinaImage(benchmark::State& state, const RetinaGrid& grid, double focus, double target_seconds) {
  const Workload& w = GetWorkload("paper_prototype");
  Patterns t = w.model->UniformPatterns(0.5f);
  const std::vector<PupilPoint> pupil = PupilSamples(w.system.eye);
  RetinaWorkspace workspace;
  double last = 0;
  for (auto _ : state)
    last = Timed(state, [&] {
      const DisplayRetinaTables tables(*w.model, grid, pupil, {focus, focus, focus});
      benchmark::DoNotOptimize(RetinaOfDisplay(*w.model, t, tables, &workspace).pixels.data());
    });
  state.counters["retina_samples"] = double(grid.cols) * grid.rows;
  state.counters["pupil_samples"] = double(pupil.size());
  Report(state, target_seconds, last);
}

// The grid of `layerlab retina` and the main job: the display's field at 0.05 deg (710 x 364 for the prototype).
RetinaGrid RetinaSweepGrid(const Workload& w) {
  return Settings().smoke ? MakeRetinaGrid(4 * kRadiansPerDegree, 2 * kRadiansPerDegree, 0.1 * kRadiansPerDegree)
                          : MakeRetinaGrid(w.system.fov_x_rad, w.system.fov_y_rad, 0.05 * kRadiansPerDegree);
}

void BM_RetinaImage(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  DisplayRetinaImage(state,
                     Settings().smoke
                         ? MakeRetinaGrid(4 * kRadiansPerDegree, 2 * kRadiansPerDegree, 0.1 * kRadiansPerDegree)
                         : MakeRetinaGrid(w.system.fov_x_rad, w.system.fov_y_rad, w.system.fov_x_rad / 400),
                     1.3, 0.020);
}

// One accommodation state of the focal stack: the display's retinal image.
void BM_RetinaImageOfDisplay(benchmark::State& state) {
  DisplayRetinaImage(state, RetinaSweepGrid(GetWorkload("paper_prototype")), 1.0, 0.010);
}

// The same state through an eye that diffracts (retina/eye_optics.h): the
// grid widened by the PSF's support; with the MTF, the geometric image times
// the diffraction-limited MTF; by the pupil function, the pupil's groups
// traced and transformed, its parts of the OTF made once, outside the timing,
// as a sweep makes them.
void DiffractedRetinaImage(benchmark::State& state, EyeDiffraction diffraction) {
  const Workload& w = GetWorkload("paper_prototype");
  const RetinaGrid grid = RetinaSweepGrid(w);
  EyeModel eye = w.system.eye;
  eye.diffraction = diffraction;
  Patterns t = w.model->UniformPatterns(0.5f);
  const std::vector<PupilPoint> pupil = PupilSamples(eye);
  const EyeOptics optics(eye, pupil, grid);
  RetinaWorkspace workspace;
  double last = 0;
  for (auto _ : state)
    last = Timed(state, [&] {
      const Image image = optics.See([&](const RetinaGrid& traced, const std::vector<PupilPoint>& group) {
        return RetinaOfDisplay(*w.model, t, DisplayRetinaTables(*w.model, traced, group, {1.0, 1.0, 1.0}), &workspace);
      });
      benchmark::DoNotOptimize(image.pixels.data());
    });
  state.counters["retina_samples"] = double(grid.cols) * grid.rows;
  state.counters["traced_samples"] = double(optics.traced().cols) * optics.traced().rows;
  state.counters["transformed_groups"] = double(optics.transformed_groups());
  Report(state, 0.030, last);
}

void BM_RetinaImageOfDisplayMtf(benchmark::State& state) { DiffractedRetinaImage(state, EyeDiffraction::kPupilMtf); }
void BM_RetinaImageOfDisplayWave(benchmark::State& state) {
  DiffractedRetinaImage(state, EyeDiffraction::kPupilFunction);
}

// The same state of natural viewing of the target: image-wise (RetinaOfScene
// of a light field) and, for the ratio, the radiance called per ray.
void NaturalRetinaImage(benchmark::State& state, bool ray_by_ray) {
  const Workload& w = GetWorkload("paper_prototype");
  const RetinaGrid grid = RetinaSweepGrid(w);
  const std::vector<PupilPoint> pupil = PupilSamples(w.system.eye);
  const SceneRadiance natural = LightFieldRadiance(w.target);
  double last = 0;
  for (auto _ : state)
    last = Timed(state, [&] {
      Image image = ray_by_ray ? RetinaOfSceneRayByRay(natural, grid, pupil, {1.0, 1.0, 1.0})
                               : RetinaOfScene(natural, grid, pupil, {1.0, 1.0, 1.0});
      benchmark::DoNotOptimize(image.pixels.data());
    });
  state.counters["retina_samples"] = double(grid.cols) * grid.rows;
  state.counters["pupil_samples"] = double(pupil.size());
  Report(state, ray_by_ray ? 1.5 : 0.020, last);
  state.SetLabel(w.target_name);
}
void BM_NaturalRetinaImage(benchmark::State& state) { NaturalRetinaImage(state, false); }
void BM_NaturalRetinaImageRayByRay(benchmark::State& state) { NaturalRetinaImage(state, true); }

// A folder of its own under the system's temporary directory, removed when done.
struct ScratchFolder {
  std::filesystem::path path;
  explicit ScratchFolder(const std::string& name)
      : path(std::filesystem::temp_directory_path() / (name + "_" + std::to_string(getpid()))) {
    std::filesystem::remove_all(path);
  }
  ~ScratchFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

// The main job's focal stack as `layerlab retina --target dice --accommodation
// 0.4,1.0,1.6,2.2 --focal-stack 0:2.6:0.1` runs it: the dice read, the model
// made, 27 states of display and natural images written (EXR + PNG), here of
// uniform patterns of 0.5. Smoke: the synthetic target, 2 coarse states.
void BM_FocalStack(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  const bool smoke = Settings().smoke;
  const std::string dice = std::string(LAYERLAB_DATA_DIR) + "/dice";
  const bool read_dice = w.target_name == "dice";
  RetinaSweepOptions o;
  if (smoke) {
    o.states_diopters = {0.4, 1.6}, o.resolution_deg = 0.1, o.field_x_deg = 4, o.field_y_deg = 2;
  } else {
    o.states_diopters = {0.4, 1.0, 1.6, 2.2};
    for (int k = 0; k <= 26; ++k)
      if (k != 4 && k != 10 && k != 16 && k != 22) o.states_diopters.push_back(0.1 * k);
    std::sort(o.states_diopters.begin(), o.states_diopters.end());
  }
  ScratchFolder out("layerlab_bench_focal_stack");
  double last = 0;
  for (auto _ : state)
    last = Timed(state, [&] {
      const LightField target = read_dice ? ReadLightField(dice, {.load_depth = false}) : w.target;
      const DisplayModel model(w.system, target.geometry);
      const Patterns t = model.UniformPatterns(0.5f);
      const std::vector<RetinaStateResult> r =
          WriteRetinaSweep(model, t, LightFieldRadiance(target), o, out.path.string(), nullptr);
      benchmark::DoNotOptimize(r.data());
    });
  state.counters["states"] = double(o.states_diopters.size());
  Report(state, 2.0, last);
  state.SetLabel(w.target_name);
}

// The Fig. 5 sweep as `layerlab contrast examples/additive_2layer.json
// examples/multiplicative_2layer.json examples/paper_prototype.json` runs it:
// 3 displays x 3 depths x 2 frequencies, each solved on a strip and swept
// over accommodation. Smoke: one display, depth and frequency, a coarse sweep.
void BM_Fig5Sweep(benchmark::State& state) {
  const bool smoke = Settings().smoke;
  std::vector<ContrastDisplay> displays;
  for (const char* example : {"additive_2layer", "multiplicative_2layer", "paper_prototype"}) {
    displays.push_back(LoadContrastDisplay(std::string(LAYERLAB_SOURCE_DIR) + "/examples/" + example + ".json"));
    if (smoke) break;
  }
  ContrastOptions o;
  if (smoke) {
    o.target_diopters = {1.3}, o.frequencies_cpd = {2.0};
    o.accommodation_step_diopters = 0.65, o.retina_field_deg = 4, o.retina_resolution_deg = 0.05, o.strip_rows = 4;
    for (ContrastDisplay& d : displays) {
      if (!d.options_given)
        d.options = SolverRegistry::Builtins().find(d.solver.empty() ? DefaultSolverFor(d.system) : d.solver)->defaults;
      d.options_given = true;
      d.options.iterations = std::min(d.options.iterations, 3);
    }
  }
  size_t curves = 0;
  double last = 0;
  for (auto _ : state) last = Timed(state, [&] { curves = RunContrast(displays, o).size(); });
  state.counters["curves"] = double(curves);
  Report(state, 8.0, last);
}

// ---- The paper's formulation: P_k as explicit sparse matrices (rays x pixels). ----

using SparseP = Eigen::SparseMatrix<float, Eigen::RowMajor, int>;
using RaysRgb = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;

SparseP BuildSparse(const LayerProjection& P) {
  const LightFieldGeometry& g = P.geometry();
  std::vector<Eigen::Triplet<float, int>> entries;
  entries.reserve(g.ray_count());
  for (size_t v = 0; v < g.view_count(); ++v)
    P.ForEachTap(v, [&](size_t ray, int32_t pixel, float weight) {
      entries.emplace_back(static_cast<int>(v * g.pixels_per_view() + ray), pixel, weight);
    });
  SparseP m(static_cast<int>(g.ray_count()), static_cast<int>(P.pixel_count()));
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

Eigen::Map<const RaysRgb> AsMatrix(const std::vector<float>& v) {
  return {v.data(), static_cast<Eigen::Index>(v.size() / 3), 3};
}

struct SparseModel {
  std::vector<SparseP> P;
  double build_seconds = 0;
};
const SparseModel& GetSparse(const std::string& example) {
  static std::map<std::string, SparseModel> cache;
  auto it = cache.find(example);
  if (it != cache.end()) return it->second;
  const Workload& w = GetWorkload(example);
  SparseModel s;
  auto start = std::chrono::steady_clock::now();
  for (size_t k = 0; k < w.model->layer_count(); ++k) s.P.push_back(BuildSparse(w.model->projection(k)));
  s.build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return cache.emplace(example, std::move(s)).first->second;
}

void BM_SynthesisSparse(benchmark::State& state) {
  const Workload& w = GetWorkload("paper_prototype");
  const SparseModel& s = GetSparse("paper_prototype");
  Patterns t = w.model->UniformPatterns(0.5f);
  for (auto _ : state) {
    RaysRgb total = RaysRgb::Zero(s.P[0].rows(), 3);
    for (size_t b = 0; b < w.model->branch_count(); ++b) {
      RaysRgb product = RaysRgb::Ones(s.P[0].rows(), 3);
      for (int k : w.model->branch_layers(b)) product = product.cwiseProduct(s.P[k] * AsMatrix(t[k].rgb));
      total += product;
    }
    benchmark::DoNotOptimize(total.data());
  }
  state.counters["build_s"] = s.build_seconds;
  state.counters["peak_rss_MB"] = PeakRssMb();
}

// One multiplicative 2-layer iteration (each layer updated once) with sparse
// matrices: t_a <- t_a * P_a^T (l o Q) / P_a^T ((P_a t_a) o Q o Q), Q = P_b t_b.
void BM_MultiplicativeIterationSparse(benchmark::State& state) {
  const Workload& w = GetWorkload("multiplicative_2layer");
  const SparseModel& s = GetSparse("multiplicative_2layer");
  Patterns t = w.model->UniformPatterns(0.5f);
  Eigen::Map<const RaysRgb> l(w.target.rgb.data(), s.P[0].rows(), 3);
  for (auto _ : state) {
    for (int a = 0; a < 2; ++a) {
      const int b = 1 - a;
      RaysRgb q = s.P[b] * AsMatrix(t[b].rgb);
      RaysRgb num = s.P[a].transpose() * l.cwiseProduct(q);
      RaysRgb den = s.P[a].transpose() * (s.P[a] * AsMatrix(t[a].rgb)).cwiseProduct(q).cwiseProduct(q);
      for (size_t k = 0; k < t[a].rgb.size(); ++k) {
        float d = den.data()[k];
        if (d > 1e-12f) t[a].rgb[k] = std::clamp(t[a].rgb[k] * num.data()[k] / d, 1e-6f, 1.0f);
      }
    }
  }
  state.counters["build_s"] = s.build_seconds;
  state.counters["peak_rss_MB"] = PeakRssMb();
}

}  // namespace
}  // namespace layerlab::bench

using namespace layerlab::bench;
BENCHMARK(BM_Synthesis)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MemoryFloorRead)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MemoryFloorCopy)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_UpdatePass)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PairLatticeUpdate)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PairLatticeBin)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ObjectivePass)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_JointPass)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_HybridIteration)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_HybridIterationRealLens)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_RetinalObjectiveIteration)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_RetinalPass)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);
BENCHMARK(BM_RetinalOperator)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(5);
BENCHMARK(BM_AdditiveGramApply)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MultiplicativeIteration)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_RankKIteration)
    ->ArgsProduct({{0, 1}, {1, 2, 4}})
    ->ArgNames({"solver", "K"})
    ->Unit(benchmark::kMillisecond)
    ->UseManualTime();
BENCHMARK(BM_RetinaImage)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_RetinaImageOfDisplay)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_RetinaImageOfDisplayMtf)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_RetinaImageOfDisplayWave)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_NaturalRetinaImage)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_NaturalRetinaImageRayByRay)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(2);
BENCHMARK(BM_FocalStack)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_Fig5Sweep)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_HybridSchedule)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_QuasiNewtonToHybridSchedulePsnr)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_AdditiveToConvergence)->Unit(benchmark::kMillisecond)->UseManualTime()->Iterations(1);
BENCHMARK(BM_SynthesisSparse)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MultiplicativeIterationSparse)->Unit(benchmark::kMillisecond)->UseRealTime();

int main(int argc, char** argv) {
  std::vector<char*> args;
  for (int k = 0; k < argc; ++k) {
    if (std::strcmp(argv[k], "--smoke") == 0) {
      Settings().smoke = true;
      continue;
    }
    args.push_back(argv[k]);
  }
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

#include "layerlab/analysis/frame_sequence.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/huge_page_allocator.h"
#include "layerlab/framework/units.h"
#include "layerlab/solvers/solver.h"
#if LAYERLAB_WITH_EMBREE
#include "layerlab/targets/target_renderer.h"
#endif

namespace layerlab {
namespace {

using Clock = std::chrono::steady_clock;

// What the frames' renders and solves may keep of the large buffers they free, for the next frame to reuse
// (framework/huge_page_allocator.h): more than a paper-scale frame makes and frees.
constexpr size_t kKeptBytes = size_t(2) << 30;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The RMS change of each layer's pattern between two solutions of one display.
std::vector<double> LayerChange(const Patterns& before, const Patterns& now) {
  std::vector<double> change(now.size(), 0.0);
  for (size_t k = 0; k < now.size(); ++k) {
    double sum = 0;
    for (size_t i = 0; i < now[k].rgb.size(); ++i) {
      const double d = double(now[k].rgb[i]) - double(before[k].rgb[i]);
      sum += d * d;
    }
    change[k] = now[k].rgb.empty() ? 0.0 : std::sqrt(sum / double(now[k].rgb.size()));
  }
  return change;
}

// One solve of `lf` from `start` (nullptr: the solver's first guess); the wall time with its setup.
SolverReport SolveFrame(const SolveJob& job, const DisplayModel& model, const LightField& lf, SolverOptions options,
                        const Patterns* start, Patterns* patterns, double* seconds) {
  options.initial_patterns = start;
  const Clock::time_point t0 = Clock::now();
  SolverReport report = SolverRegistry::Builtins().create(job.config.solver)->Solve(model, lf, options, patterns);
  *seconds = SecondsSince(t0);
  return report;
}

void RequireUsable(const SolverReport& report, int frame, const char* which) {
  if (!report.IsSolutionUsable())
    throw Error("frame " + std::to_string(frame) + ": the " + which + " solve failed: " + report.message + " (" +
                report.BriefReport() + ")");
}

}  // namespace

void RequireFrameSequence(const SolveJob& job, const TargetScene& scene, const FrameSequenceOptions& options) {
  if (options.frames < 1) throw Error("--frames: must be at least 1");
  if (options.frame_iterations < 1) throw Error("--frame-iterations: must be at least 1");
  if (options.cold_every < 0) throw Error("--cold-every: must be 0 (no cold solves) or positive");
  if (!TargetSceneMoves(scene))
    throw Error(
        scene.file +
        ": the target scene does not move (no camera keys in \"animation\" and no mesh \"keys\"), so every frame "
        "would be the same; docs/target-format.md, \"Moving scenes\"");
  if (job.config.options.objective == ObjectiveKind::kRetinal || job.config.options.measure_focal_stack)
    throw Error(
        "a frame sequence solves the light-field objective; the retinal objective and the focal stack are for "
        "one frame");
}

FrameSequence SolveFrameSequence(const SolveJob& job, const TargetScene& scene, const FrameSequenceOptions& options,
                                 const std::function<void(const FrameRow&)>& on_frame) {
  RequireFrameSequence(job, scene, options);
#if !LAYERLAB_WITH_EMBREE
  throw Error("--frames renders each frame's target, and this layerlab was built without Embree");
#else
  const LargeBlockReuse reuse(kKeptBytes);
  FrameSequence sequence;
  std::shared_ptr<DisplayModel> model;
  Patterns previous;
  for (int f = 0; f < options.frames; ++f) {
    FrameRow row;
    row.frame = f;
    row.time_s = f / scene.animation->frame_rate_hz;
    const Clock::time_point t0 = Clock::now();
    const LightField lf = RenderTarget(TargetSceneAt(scene, row.time_s));
    row.render_seconds = SecondsSince(t0);
    if (!model) {
      model = std::make_shared<DisplayModel>(*job.system, lf.geometry, job.config.sampling);
      for (size_t k = 0; k < model->layer_count(); ++k) sequence.layer_names.push_back(job.system->layers[k].name);
    }
    SolverOptions warm = job.config.options;
    if (f > 0) warm.iterations = options.frame_iterations;
    Patterns patterns;
    SolverReport report = SolveFrame(job, *model, lf, warm, f > 0 ? &previous : nullptr, &patterns, &row.solve_seconds);
    RequireUsable(report, f, f > 0 ? "warm" : "first");
    row.iterations = report.iterations;
    row.psnr_db = report.final_psnr_db;
    if (f == 0) {
      row.cold_psnr_db = row.psnr_db, row.cold_seconds = row.solve_seconds;
    } else if (options.cold_every > 0 && f % options.cold_every == 0) {
      Patterns cold;
      const SolverReport c = SolveFrame(job, *model, lf, job.config.options, nullptr, &cold, &row.cold_seconds);
      RequireUsable(c, f, "cold");
      row.cold_psnr_db = c.final_psnr_db;
    }
    row.layer_change = f > 0 ? LayerChange(previous, patterns) : std::vector<double>(patterns.size(), 0.0);
    previous = patterns;
    sequence.rows.push_back(row);
    if (on_frame) on_frame(row);
    if (f + 1 == options.frames) {
      sequence.last.model = model;
      sequence.last.patterns = std::move(patterns);
      sequence.last.report = std::move(report);
    }
  }
  return sequence;
#endif
}

void WriteFramesCsv(const FrameSequence& sequence, const std::string& path) {
  std::ostringstream out;
  out << "frame,time_s,render_s,solve_s,iterations,psnr_db,cold_psnr_db,cold_solve_s,psnr_below_cold_db";
  for (const std::string& name : sequence.layer_names) out << ",change_" << name;
  out << "\n";
  char line[256];
  for (const FrameRow& r : sequence.rows) {
    std::snprintf(line, sizeof line, "%d,%.6f,%.6f,%.6f,%d,%.6f,%.6f,%.6f,%.6f", r.frame, r.time_s, r.render_seconds,
                  r.solve_seconds, r.iterations, r.psnr_db, r.cold_psnr_db, r.cold_seconds, r.cold_psnr_db - r.psnr_db);
    out << line;
    for (double c : r.layer_change) {
      std::snprintf(line, sizeof line, ",%.8f", c);
      out << line;
    }
    out << "\n";
  }
  WriteFileAtomically(path, out.str());
}

std::string FramesSummary(const FrameSequence& sequence, const FrameSequenceOptions& options,
                          const TargetScene& scene) {
  const std::vector<FrameRow>& rows = sequence.rows;
  std::ostringstream out;
  char line[512];
  const FrameRow& first = rows.front();
  std::snprintf(line, sizeof line, "%zu frames of %s at %.4g Hz (%.4f to %.4f s)\n", rows.size(), scene.file.c_str(),
                scene.animation->frame_rate_hz, first.time_s, rows.back().time_s);
  out << line;
  std::snprintf(line, sizeof line, "frame 0: cold, %d iterations in %.3f s, PSNR %.2f dB; its render %.3f s\n",
                first.iterations, first.solve_seconds, first.psnr_db, first.render_seconds);
  out << line;
  if (rows.size() < 2) return out.str();
  std::vector<double> solve, render, below;
  double psnr = 0;
  for (size_t f = 1; f < rows.size(); ++f) {
    solve.push_back(rows[f].solve_seconds), render.push_back(rows[f].render_seconds);
    psnr += rows[f].psnr_db;
    if (!std::isnan(rows[f].cold_psnr_db)) below.push_back(rows[f].cold_psnr_db - rows[f].psnr_db);
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  const double per_frame = median(solve);
  std::snprintf(line, sizeof line,
                "frames 1-%zu: %d iterations each from the frame before: %.3f s a frame (median), %.2f frames/s of "
                "factorization; render %.3f s a frame (median)\n",
                rows.size() - 1, options.frame_iterations, per_frame, 1 / per_frame, median(render));
  out << line;
  std::snprintf(line, sizeof line, "  PSNR %.2f dB (mean)", psnr / double(rows.size() - 1));
  out << line;
  if (!below.empty()) {
    double mean = 0, worst = -INFINITY;
    for (double b : below) mean += b, worst = std::max(worst, b);
    std::snprintf(line, sizeof line,
                  "; below the cold solve of the same frame by %.3f dB (mean), %.3f dB (worst), over %zu "
                  "frame%s compared",
                  mean / double(below.size()), worst, below.size(), below.size() == 1 ? "" : "s");
    out << line;
  }
  out << "\n  change between frames (RMS linear transmittance, mean):";
  for (size_t k = 0; k < sequence.layer_names.size(); ++k) {
    double sum = 0;
    for (size_t f = 1; f < rows.size(); ++f) sum += rows[f].layer_change[k];
    std::snprintf(line, sizeof line, " %s %.4f", sequence.layer_names[k].c_str(), sum / double(rows.size() - 1));
    out << line;
  }
  out << "\n";
  return out.str();
}

}  // namespace layerlab

#include "layerlab/design/design_starts.h"

#include <cstdio>
#include <filesystem>
#include <optional>

#include "layerlab/framework/error.h"
#include "layerlab/framework/file_lock.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

// The radical inverse of i in base b: the Halton sequence's coordinate.
double RadicalInverse(unsigned long long i, unsigned b) {
  double inverse = 1.0 / b, f = inverse, r = 0;
  while (i > 0) {
    r += f * static_cast<double>(i % b);
    i /= b;
    f *= inverse;
  }
  return r;
}

constexpr unsigned kPrimes[] = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29,  31,  37,  41,  43,  47,  53,
                                59, 61, 67, 71, 73, 79, 83, 89, 97, 101, 103, 107, 109, 113, 127, 131};

}  // namespace

std::vector<std::vector<double>> MultistartPoints(const DesignSpec& spec) {
  const size_t n = spec.variables.size();
  if (n > std::size(kPrimes)) throw Error("internal error: a multistart of more than 32 variables");
  std::vector<std::vector<double>> points;
  std::vector<double> x0;
  for (const DesignVariable& v : spec.variables) x0.push_back(v.start);
  points.push_back(x0);
  const unsigned long long first = 1ull + spec.optimizer.seed;  // index 0 is the box's corner
  constexpr unsigned long long kTries = 100000;
  for (unsigned long long i = first; i < first + kTries && points.size() < static_cast<size_t>(spec.optimizer.starts);
       ++i) {
    std::vector<double> x(n);
    for (size_t k = 0; k < n; ++k) {
      const DesignVariable& v = spec.variables[k];
      x[k] = v.min + RadicalInverse(i, kPrimes[k]) * (v.max - v.min);
    }
    if (MeetsLinearConstraints(spec, x)) points.push_back(x);
  }
  if (points.size() < static_cast<size_t>(spec.optimizer.starts))
    throw Error(Location{spec.file, "/optimizer/starts"},
                "only " + std::to_string(points.size() - 1) + " of the first " + std::to_string(kTries) +
                    " points spread over the variables' bounds meet the linear constraints, fewer than the " +
                    std::to_string(spec.optimizer.starts - 1) +
                    " starts beside the design's own: the constraints leave too thin a region; ask fewer starts");
  return points;
}

int StartBudget(const DesignSpec& spec, int k) {
  const int starts = spec.optimizer.starts, total = spec.optimizer.evaluations;
  return total / starts + (k < total % starts ? 1 : 0);
}

std::string StartId(int k) {
  char text[16];
  std::snprintf(text, sizeof text, "s%02d", k);
  return text;
}

StartOutcome RunStart(const DesignSpec& spec, const std::string& out, int k) {
  if (k < 0 || k >= spec.optimizer.starts)
    throw Error("--start " + std::to_string(k) + ": the design has starts 0 to " +
                std::to_string(spec.optimizer.starts - 1));
  const std::vector<std::vector<double>> points = MultistartPoints(spec);
  const fs::path folder = fs::path(out) / "starts" / StartId(k);
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw Error(folder.string() + ": cannot create the folder: " + ec.message());
  std::string holder;
  const std::optional<FileLock> lock = FileLock::TryLock((folder / "start.lock").string(), &holder);
  if (!lock)
    throw Error(out + ": start " + StartId(k) + " is running in another process" +
                (holder.empty() ? "" : " (" + holder + ")") + "; wait for it to end");
  DesignEvaluator evaluator(spec, out, StartId(k));
  StartOutcome outcome;
  evaluator.Resume();
  outcome.search = SearchFromStart(spec, points[static_cast<size_t>(k)], StartBudget(spec, k), &evaluator);
  outcome.asked = evaluator.asked();
  outcome.ran = evaluator.ran();
  outcome.replayed = evaluator.replayed();
  return outcome;
}

MultistartRecord::MultistartRecord(const DesignSpec& spec, const std::string& out) {
  for (int k = 0; k < spec.optimizer.starts; ++k) {
    // Held while the log is read (Resume cuts an unfinished last line): a start running now would append to it.
    const fs::path folder = fs::path(out) / "starts" / StartId(k);
    std::optional<FileLock> lock;
    if (fs::exists(folder)) {
      std::string holder;
      lock = FileLock::TryLock((folder / "start.lock").string(), &holder);
      if (!lock)
        throw Error(out + ": start " + StartId(k) + " is still running" + (holder.empty() ? "" : " (" + holder + ")") +
                    "; gather once every start has ended");
    }
    starts_.push_back(std::make_unique<DesignEvaluator>(spec, out, StartId(k)));
    if (starts_.back()->Resume() == 0) missing_.push_back(StartId(k));
    for (const DesignEvaluation* e : starts_.back()->evaluations()) all_.push_back(e);
  }
}

}  // namespace layerlab

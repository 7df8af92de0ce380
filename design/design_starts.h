// A multistart (optimizer.global "multistart"): independent local searches
// from `starts` points, each with its share of the evaluations, its own log
// and its own evaluation ids (DIR/starts/s01/evaluations.jsonl, s01-e0003).
// Since no start reads another's evaluations, the starts can run in any order
// and in parallel (`optimize --local -j N`, `--mpi`, `--slurm`), and each
// gives the same designs however it is run; the report gathers them all.
//
// Start 0 is the design's own start. Start k > 0 is a point of the Halton
// sequence over the variables' bounds (bases 2, 3, 5, ..., the first `seed`
// points skipped, and each point that misses a linear constraint), so that
// the starts fill the feasible box evenly and the same on every run.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "layerlab/design/design_evaluator.h"
#include "layerlab/design/design_search.h"

namespace layerlab {

// The starts' points, in the variables' units. Throws layerlab::Error naming
// /optimizer/starts when too few points of the sequence meet the linear constraints.
std::vector<std::vector<double>> MultistartPoints(const DesignSpec& spec);

// Start k's evaluations: the budget split as evenly as it goes, the first starts taking the remainder.
int StartBudget(const DesignSpec& spec, int k);

// "s00", "s01", ...: the start's folder under DIR/starts and its evaluations' prefix.
std::string StartId(int k);

struct StartOutcome {
  DesignSearch search;
  size_t asked = 0, ran = 0, replayed = 0;
};

// Runs start k into DIR (resuming from its log), holding DIR/starts/sKK/start.lock:
// a start that another process is running is refused with that process named.
StartOutcome RunStart(const DesignSpec& spec, const std::string& out, int k);

// Every start's evaluations read back from their logs, start by start.
class MultistartRecord {
 public:
  MultistartRecord(const DesignSpec& spec, const std::string& out);
  const std::vector<const DesignEvaluation*>& evaluations() const { return all_; }
  // The starts' evaluators (one per start), e.g. for JobsOf.
  const DesignEvaluator& start(int k) const { return *starts_[static_cast<size_t>(k)]; }
  // The starts whose logs hold no evaluation (not run yet).
  std::vector<std::string> missing() const { return missing_; }

 private:
  std::vector<std::unique_ptr<DesignEvaluator>> starts_;
  std::vector<const DesignEvaluation*> all_;
  std::vector<std::string> missing_;
};

}  // namespace layerlab

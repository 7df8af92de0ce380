// The evaluations of `layerlab optimize` (design/design_spec.h): each design
// the optimizer asks for is the base scene with its variables written in, run
// once per target as a sweep job (analysis/sweep_jobs.h), and its metrics read
// from the jobs' rows.
//
//   DIR/jobs/e0007[-t1]/     the job of evaluation 7 (on target 1), as a sweep's
//   DIR/evaluations.jsonl    one line per finished evaluation: {index, id, x, warm_start}
//   DIR/starts/s01/evaluations.jsonl   the same for start 1 of a multistart, whose
//                            evaluations are s01-e0000, ... (design/design_starts.h)
//   DIR/targets/<key>/       the targets' renders, shared by every evaluation
//
// An optimization that was killed resumes from its log: the optimizer replays
// its (deterministic) sequence, and every design the log holds, with its jobs
// complete for the same scene, is answered from its job.json without a solve.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "layerlab/analysis/sweep_jobs.h"
#include "layerlab/design/design_spec.h"

namespace layerlab {

struct DesignEvaluation {
  size_t index = 0;
  std::string id;         // "e0007", or "s01-e0007" in start 1 of a multistart
  std::string start;      // "s01" in a multistart, else ""
  std::vector<double> x;  // in the variables' units
  bool failed = false;
  std::string error;
  std::vector<double> metrics;  // per DesignSpec::metrics, the mean over the targets
  double loss = 0;              // what the optimizer minimizes (DesignSpec's objective)
  double seconds = 0;           // wall time of its jobs
  std::string warm_start;       // the evaluation whose patterns its solves began from, or ""
  bool from_log = false;        // read back from an earlier run's log, not run here
};

class DesignEvaluator {
 public:
  // Reads and writes nothing yet. `start` ("s01") names one start of a
  // multistart: its own log and evaluation ids; "" for a single search.
  DesignEvaluator(const DesignSpec& spec, std::string out, std::string start = "");
  DesignEvaluator(const DesignEvaluator&) = delete;  // asked_ points into done_
  DesignEvaluator& operator=(const DesignEvaluator&) = delete;

  // Reads DIR/evaluations.jsonl when there is one (an earlier run's): the
  // evaluations whose jobs are finished for the same scenes; returns how many.
  size_t Resume();

  // The evaluation of design x: from the log or an earlier call when x (to the
  // bit) was evaluated, else run now. A failed run is an evaluation too
  // (`failed`, with its error): it is not run again.
  const DesignEvaluation& Evaluate(const std::vector<double>& x);

  // Every evaluation asked for in this process or found in the log, by index.
  std::vector<const DesignEvaluation*> evaluations() const;
  // The designs asked for in this process, in the order asked. What the search
  // decides from (FailedLoss, Nearest, the best so far) is read from these
  // only, never from log entries it has not asked for yet: a resumed search
  // then sees what an uninterrupted one saw at the same point.
  const std::vector<const DesignEvaluation*>& asked_in_order() const { return asked_; }
  size_t asked() const { return asked_.size(); }
  size_t ran() const { return ran_; }            // solved in this process
  size_t replayed() const { return replayed_; }  // asked again and answered from the log
  // The loss of a failed evaluation: worse than every evaluation asked so far, so that the search turns away.
  double FailedLoss() const;
  // The jobs of an evaluation (one per target), for the report's links.
  std::vector<SweepJob> JobsOf(const DesignEvaluation& e) const;
  // The base scene with design x written in (relative paths as the base scene's).
  nlohmann::ordered_json SceneWith(const std::vector<double>& x) const;

  const SweepSpec& sweep() const { return sweeps_.front(); }
  const std::string& log_path() const { return log_; }
  const std::string& out() const { return out_; }

 private:
  std::string IdOf(size_t index) const;
  void AppendLog(const DesignEvaluation& e) const;
  std::vector<SceneValue> ValuesOf(const std::vector<double>& x) const;
  // The design asked so far nearest x (relative to the bounds) that ran, or null.
  const DesignEvaluation* Nearest(const std::vector<double>& x) const;
  void Score(DesignEvaluation* e, const std::vector<SweepJobState>& states) const;

  const DesignSpec& spec_;
  std::string out_, start_, log_;
  std::vector<SweepSpec> sweeps_;  // one per target: the job settings and the base scene with that target
  std::map<std::vector<double>, DesignEvaluation> done_;
  std::map<std::vector<double>, size_t> logged_index_;  // every design in the log, finished or not
  std::vector<const DesignEvaluation*> asked_;          // into done_, whose nodes do not move
  size_t next_index_ = 0, ran_ = 0, replayed_ = 0;
};

}  // namespace layerlab

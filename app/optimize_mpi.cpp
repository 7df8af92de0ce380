// `mpirun -np N layerlab optimize DESIGN.json --out DIR --mpi`: a multistart's
// starts dealt to the ranks, start k to rank k mod N (the same split on every
// run, so that a resumed run gives each rank the same starts). Only rank 0
// writes the report, after every rank has ended.
#include <exception>

#include "layerlab/app/optimize_runners.h"
#include "layerlab/design/design_starts.h"
#include "layerlab/framework/mpi_world.h"
#include "layerlab/framework/progress.h"

namespace layerlab::app {

size_t RunStartsMpi(const DesignSpec& spec, const std::string& out, bool* is_root) {
  const MpiWorld world;
  *is_root = world.rank() == 0;
  // A rank that cannot go on ends every rank: the others would wait at the next barrier for ever.
  size_t earlier = 0;
  try {
    if (world.rank() == 0) earlier = MultistartRecord(spec, out).evaluations().size();
  } catch (const std::exception& e) {
    world.Abort(e.what());
  }
  world.Barrier();  // counted before any rank starts
  try {
    for (int k = world.rank(); k < spec.optimizer.starts; k += world.size()) {
      const StartOutcome o = RunStart(spec, out, k);
      Note("optimize: rank " + std::to_string(world.rank()) + ": start " + StartId(k) + ": " + std::to_string(o.asked) +
           " evaluations (" + std::to_string(o.ran) + " run); stopped because " + o.search.stopped);
    }
  } catch (const std::exception& e) {
    world.Abort(e.what());
  }
  world.Barrier();
  return earlier;
}

}  // namespace layerlab::app

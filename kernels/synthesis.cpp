#include "layerlab/kernels/synthesis.h"

#include <omp.h>

#include <optional>

#include "layerlab/framework/error.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/kernels/view_synthesizer.h"

namespace layerlab {

LightField Synthesize(const DisplayModel& model, const Patterns& t) {
  LightField lf(model.geometry());
  Synthesize(model, t, &lf);
  return lf;
}

void Synthesize(const DisplayModel& model, const Patterns& t, LightField* out, SolveWorkspace* workspace) {
  const LightFieldGeometry& lf = model.geometry();
  if (out->rgb.size() != lf.ray_count() * 3)
    throw Error("Synthesize: the output light field has other rays than the model");
  out->geometry = lf;
  const size_t views = lf.view_count();
  std::optional<SolveWorkspace> own;
  if (!workspace) workspace = &own.emplace(model, omp_get_max_threads(), kSynthesisPass);
  const ViewSynthesizer synthesizer(model, t, workspace);
#pragma omp parallel for schedule(static)
  for (size_t k = 0; k < views; ++k) {
    const size_t v = synthesizer.ViewInColumnOrder(k);
    synthesizer.View(v, out->view(v));
  }
}

}  // namespace layerlab

// A program that uses layerlab as a library: loads a scene, compiles it,
// makes a small target the display can show (its own light field of two
// known pattern sets mixed), solves it and prints the PSNR.
//   consumer SCENE.json [ITERATIONS]
#include <cstdio>
#include <cstdlib>
#include <exception>

#include <layerlab/layerlab.h>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: consumer SCENE.json [ITERATIONS]\n");
    return 2;
  }
  try {
    const layerlab::Scene scene = layerlab::LoadScene(argv[1]);
    const layerlab::DisplaySystem system = layerlab::Compile(scene);
    const layerlab::DisplayModel model(system, layerlab::DisplayLightFieldGeometry(system));

    // A reachable target: every pattern a horizontal ramp of transmittance.
    layerlab::Patterns truth = model.UniformPatterns(0.5f);
    for (layerlab::LayerPattern& p : truth)
      for (int i = 0; i < p.rows; ++i)
        for (int j = 0; j < p.cols; ++j)
          for (int c = 0; c < 3; ++c) p.rgb[(static_cast<size_t>(i) * p.cols + j) * 3 + c] = 0.2f + 0.6f * j / p.cols;
    const layerlab::LightField target = Synthesize(model, truth);

    const std::string solver = layerlab::DefaultSolverFor(system);
    layerlab::SolverOptions options = layerlab::SolverRegistry::Builtins().get(solver).defaults;
    options.iterations = argc > 2 ? std::atoi(argv[2]) : 10;
    layerlab::Patterns patterns;
    const layerlab::SolverReport report =
        layerlab::SolverRegistry::Builtins().create(solver)->Solve(model, target, options, &patterns);
    if (!report.IsSolutionUsable()) {
      std::fprintf(stderr, "consumer: %s\n", report.message.c_str());
      return 1;
    }
    std::printf("%s: %zu layers, %zu branches; %s, %d iterations: PSNR %.2f dB\n", system.name.c_str(),
                system.layers.size(), system.branches.size(), solver.c_str(), report.iterations, report.final_psnr_db);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}

// exr_difference A.exr B.exr: the largest difference between two EXR images of
// the same size (R, G, B), relative to the largest value of A, on stdout;
// exit 2 when they cannot be compared. For the MPI tests, which compare the
// patterns of a partitioned solve with those of one process.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "layerlab/framework/exr_image.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: exr_difference A.exr B.exr\n");
    return 2;
  }
  try {
    const layerlab::Image a = layerlab::ReadExr(argv[1], {"R", "G", "B"}),
                          b = layerlab::ReadExr(argv[2], {"R", "G", "B"});
    if (a.width != b.width || a.height != b.height) {
      std::fprintf(stderr, "exr_difference: %s and %s differ in size\n", argv[1], argv[2]);
      return 2;
    }
    double largest = 0, difference = 0;
    for (size_t k = 0; k < a.pixels.size(); ++k) {
      largest = std::max(largest, std::abs(double(a.pixels[k])));
      difference = std::max(difference, std::abs(double(a.pixels[k]) - b.pixels[k]));
    }
    std::printf("%.3e\n", largest > 0 ? difference / largest : difference);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "exr_difference: %s\n", e.what());
    return 2;
  }
  return 0;
}

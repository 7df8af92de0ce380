#include "layerlab/framework/fixed_parts.h"

namespace layerlab {
namespace {

thread_local int parts_of_solve = 0;

}  // namespace

int FixedParts() { return parts_of_solve > 0 ? parts_of_solve : omp_get_max_threads(); }

ScopedParts::ScopedParts(int parts) : saved_(parts_of_solve) { parts_of_solve = parts; }
ScopedParts::~ScopedParts() { parts_of_solve = saved_; }

}  // namespace layerlab

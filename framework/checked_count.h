// Counts formed from user numbers (grid sizes, pixel counts, byte sizes) in
// checked arithmetic: a product or sum that does not fit in size_t is refused
// with a message naming what was counted, instead of wrapping to a small
// number that slips past every later limit.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <string>

#include "layerlab/framework/error.h"

namespace layerlab {

// a * b, or false when it does not fit.
inline bool MultiplyFits(size_t a, size_t b, size_t* product) { return !__builtin_mul_overflow(a, b, product); }
inline bool AddFits(size_t a, size_t b, size_t* sum) { return !__builtin_add_overflow(a, b, sum); }

// The product of `factors`; throws Error("<what>: <f1> x <f2> x ... does not fit in 64 bits") on overflow.
size_t CheckedProduct(std::initializer_list<size_t> factors, const std::string& what);
// The same at a location (file and JSON pointer).
size_t CheckedProduct(std::initializer_list<size_t> factors, const Location& where, const std::string& what);
// a + b, throwing as above.
size_t CheckedSum(size_t a, size_t b, const std::string& what);

}  // namespace layerlab

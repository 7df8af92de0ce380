#include "layerlab/framework/checked_count.h"

namespace layerlab {
namespace {

std::string Factors(std::initializer_list<size_t> factors) {
  std::string s;
  for (size_t f : factors) s += (s.empty() ? "" : " x ") + std::to_string(f);
  return s;
}

bool Product(std::initializer_list<size_t> factors, size_t* product) {
  size_t p = 1;
  for (size_t f : factors)
    if (!MultiplyFits(p, f, &p)) return false;
  *product = p;
  return true;
}

}  // namespace

size_t CheckedProduct(std::initializer_list<size_t> factors, const std::string& what) {
  size_t p = 0;
  if (!Product(factors, &p)) throw Error(what + ": " + Factors(factors) + " does not fit in 64 bits");
  return p;
}

size_t CheckedProduct(std::initializer_list<size_t> factors, const Location& where, const std::string& what) {
  size_t p = 0;
  if (!Product(factors, &p)) throw Error(where, what + ": " + Factors(factors) + " does not fit in 64 bits");
  return p;
}

size_t CheckedSum(size_t a, size_t b, const std::string& what) {
  size_t s = 0;
  if (!AddFits(a, b, &s))
    throw Error(what + ": " + std::to_string(a) + " + " + std::to_string(b) + " does not fit in 64 bits");
  return s;
}

}  // namespace layerlab

// The numbers of a .zmx file: parsing (locale-free), the lens units and the
// conversion of a quantity between them and meters. Shared by the reader and
// the writer, so that the writer can choose digits that read back exactly.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace layerlab::lenses::zmx {

// A finite number in the C syntax (an optional sign, digits, point, exponent),
// the whole token; nullopt for anything else (inf, nan, overflow, trailing text).
std::optional<double> ParseNumber(std::string_view token);

// Meters per lens unit for a UNIT line's first value (MM, CM, IN, METER);
// nullopt for other units.
std::optional<double> MetersPerUnit(std::string_view unit);

// A quantity of dimension length^power in lens units (`meters_per_unit`) to
// meters^power and back: lengths power 1, curvatures -1, the coefficient of
// r^(2n) 1 - 2n. The unit's powers are repeated products, not std::pow.
double ToMeters(double value, int power, double meters_per_unit);
double FromMeters(double value_si, int power, double meters_per_unit);

// `value_si` in lens units with the fewest significant digits (1 to 17) whose
// ParseNumber then ToMeters gives `value_si` again; when none does (a value no
// lens-unit number maps to), 17 digits of the nearest one. 'E' for exponents.
std::string FormatExact(double value_si, int power, double meters_per_unit);

}  // namespace layerlab::lenses::zmx

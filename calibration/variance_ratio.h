// Whether a fit's residuals exceed the noise measured apart from the fit: the
// F test of two variances. Under a right model the residuals' mean square
// over their d1 degrees of freedom, divided by the noise variance estimated
// with d2 degrees of freedom, follows F(d1, d2) (a chi-square over d1 when the
// noise is known exactly, d2 = 0 here).
#pragma once

namespace layerlab {

// z with P(Z > z) = upper_tail for a standard normal Z, upper_tail in (0, 1).
double NormalUpperQuantile(double upper_tail);

// The ratio F(d1, d2) exceeds with probability `level` (d1 >= 1; d2 = 0 for a
// noise known exactly, a chi-square over d1), by Paulson's approximation from
// Wilson and Hilferty's cube root, within a few percent of the tail down to
// tens of degrees of freedom.
double CriticalVarianceRatio(int d1, int d2, double level);

}  // namespace layerlab

// Diffraction by the panels' pixel grids (docs/optics.md, "Panel
// diffraction"). A panel whose pixels' apertures are narrower than their
// pitch (fill_factor < 1: the black matrix) is a binary amplitude grating:
// the light of a layer behind it, in the same stack, leaves it in orders
// m at sin(theta_m) = m lambda / p with the efficiency f^2 sinc^2(m f) of
// the incident power (f the fill factor; the orders sum to f, the open
// area, which the panel's max_transmittance already holds, so they are
// normalized to 1). Seen from the eye, each order is a ghost of the layer
// behind, moved in its own plane by d tan(theta_m) (d the gap between the
// two panels): a point of the layer behind is a point source for the
// panel in front, whose tilted orders appear to come from shifted points
// (paraxially exact, the angular spectrum of the field after the grating).
// The approximations, and when they hold:
//   - the orders of one point add in intensity: their cross terms carry
//     the phase 2 pi (m - n) x / p of the point's place x within the front
//     panel's period and average out over a pixel of the layer behind (a
//     diffuse backlight is spatially incoherent from point to point: its
//     coherence width, about lambda / (pi sin theta) = 0.3 um for a
//     Lambertian diffuser, is far below a pixel). A backlight coherent over
//     `coherence_width` (a collimated or laser backlight) spreads each order
//     over the angles lambda / w of its plane waves: a Gaussian of
//     sigma = d lambda / (2 pi w) in the plane of the layer behind;
//   - thin panels (the grating is the pixel plane; the LC cell's thickness
//     is not modelled), rectangular apertures (separable in x and y, each
//     axis's shift d tan(theta) of its own order), axes of the two panels
//     aligned (a stack's panels follow each other directly: nothing with
//     power lies between them);
//   - the orders of different panels in front of one layer are applied one
//     after the other, as if independent (exact for the two-panel stacks of
//     the paper's displays; for three or more panels the front panel's
//     orders move all the layers behind it together, which this does not).
#pragma once

#include <array>
#include <vector>

#include "layerlab/systems/display_model.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

struct GratingOrder {
  int m = 0;
  double angle_rad = 0;   // asin(m lambda / p)
  double efficiency = 0;  // of the incident power: f^2 sinc^2(m f)
};

// The propagating orders (|m lambda / p| < 1) with |m| <= max_order of a
// binary amplitude grating of `pitch` and open fraction `fill`.
std::vector<GratingOrder> GratingOrders(double pitch_m, double fill, double wavelength_m, int max_order);

// One axis of a layer's diffraction: the pattern read at integer offsets
// [-reach, reach] pixels with these weights (the orders' shifts spread on the
// pixel grid by linear interpolation), summing to 1.
struct DiffractionAxis {
  int reach = 0;
  std::vector<double> weight;  // 2 reach + 1
};
// What one panel in front does to one layer behind: one kernel per axis and channel.
struct LayerDiffraction {
  int layer = 0, panel_layer = 0;  // indices into DisplaySystem::layers
  double gap_m = 0;
  std::array<std::array<DiffractionAxis, 2>, 3> axes;  // [channel][x, y]
};

// Orders beyond this share of the light are left out and the rest renormalized: the sinc^2 tail beyond
// order M holds about 2 / (pi^2 M f), a faint halo, each order 1 / (pi^2 m^2) of the light.
inline constexpr double kDiffractionTail = 5e-3;

// Every pair (layer, diffracting panel in front of it in the same stack),
// at the eye's channel wavelengths, with its branch's backlight coherence
// width (0: incoherent); none when no panel diffracts.
std::vector<LayerDiffraction> PanelDiffraction(const DisplaySystem& system);

// The patterns as the eye sees them through the panels in front: each
// layer's channels convolved with its kernels (zero beyond the layer: its
// border is dark). The same patterns when no panel diffracts.
Patterns DiffractedPatterns(const std::vector<LayerDiffraction>& diffraction, const Patterns& t);
// The same into `seen`, reusing its storage (a solve's forward model, every pass).
void DiffractPatterns(const std::vector<LayerDiffraction>& diffraction, const Patterns& t, Patterns* seen);
// The transpose for one layer of rows x cols pixels: sums over its seen
// pixels ([pixel * 3 + channel], e.g. a gradient or the multiplicative
// update's two sides) become sums over its own, in place. The kernels are
// non-negative, so sums that are non-negative stay so.
void DiffractTransposed(const std::vector<LayerDiffraction>& diffraction, int layer, int rows, int cols,
                        std::vector<double>* sums);
// Whether a panel in front diffracts `layer`.
bool Diffracts(const std::vector<LayerDiffraction>& diffraction, int layer);

}  // namespace layerlab

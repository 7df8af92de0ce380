#include <algorithm>

#include "layerlab/calibration/measurements.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

const VirtualLayer& PanelNamed(const DisplaySystem& system, const std::string& name, const Location& where) {
  std::vector<std::string> names;
  for (const VirtualLayer& layer : system.layers) {
    if (layer.name == name) return layer;
    names.push_back(layer.name);
  }
  std::string msg = "no panel named \"" + name + "\" in " + (system.file.empty() ? "the scene" : system.file);
  if (auto near = ClosestWord(name, names))
    msg += "; did you mean \"" + *near + "\"?";
  else
    msg += "; its panels are " + JoinWords(names, " and ");
  throw Error(where, msg);
}

}  // namespace

void RefuseTiltedPanels(const DisplaySystem& system, const std::string& use) {
  for (const VirtualLayer& layer : system.layers)
    if (layer.panel.tilted())
      throw Error((system.file.empty() ? std::string("the scene") : system.file) + ": panel \"" + layer.element +
                  "\" has \"tilt\" [" + FormatFixed(layer.panel.tilt_rad[0] * kDegreesPerRadian, 3) + ", " +
                  FormatFixed(layer.panel.tilt_rad[1] * kDegreesPerRadian, 3) + "] deg, which " + use +
                  " cannot represent: its marker model is first order (a panel square to the axis, placed by its "
                  "distance, offset and in-plane rotation); leave \"tilt\" out of the scene for it");
}

void CheckMeasurements(const Measurements& measurements, const DisplaySystem& system) {
  RefuseTiltedPanels(system, "the calibration fit");
  for (const Capture& capture : measurements.captures)
    for (const PanelMarkers& markers : capture.panels) {
      const PanelSpec& panel = PanelNamed(system, markers.panel, markers.where).panel;
      for (const MarkerObservation& m : markers.markers) {
        const double cols = static_cast<double>(panel.resolution_cols),
                     rows = static_cast<double>(panel.resolution_rows);
        if (m.col < -0.5 || m.col > cols - 0.5 || m.row < -0.5 || m.row > rows - 0.5)
          throw Error(m.where.child("panel_pixel"),
                      "(" + FormatFixed(m.col, 1) + ", " + FormatFixed(m.row, 1) + ") is off the panel's " +
                          std::to_string(panel.resolution_cols) + " x " + std::to_string(panel.resolution_rows) +
                          " grid (columns and rows count from 0)");
      }
    }
  for (const PanelLuminance& curve : measurements.luminance) {
    PanelNamed(system, curve.panel, curve.where);
    bool lit = std::any_of(curve.samples.begin(), curve.samples.end(),
                           [](const LuminanceSample& s) { return s.luminance > 0; });
    if (!lit) throw Error(curve.where.child("samples"), "every reading is zero: the panel's response cannot be fitted");
  }
}

}  // namespace layerlab

#include "layerlab/systems/flicker_verdict.h"

#include <cstdio>

namespace layerlab {

std::string FlickerVerdict::Describe() const {
  char cff[64] = "visible at no frequency at that modulation";
  if (cff_hz > 0) std::snprintf(cff, sizeof cff, "CFF %.1f Hz at that modulation", cff_hz);
  char text[640];
  std::snprintf(text, sizeof text,
                "%s: %s; worst %.0f x %.0f deg region at (%+.1f, %+.1f) deg, %.3g cd/m2: %.3g modulation at %.0f Hz "
                "against its threshold %.3g (visibility %.3g; %s)",
                visible() ? "flicker visible" : "no visible flicker", what.c_str(), region_w_deg, region_h_deg, x_deg,
                y_deg, luminance_cd_m2, modulation, frequency_hz, modulation / (visibility > 0 ? visibility : 1),
                visibility, cff);
  return text;
}

nlohmann::json FlickerVerdict::ToJson() const {
  return {{"visible", visible()},
          {"visibility", visibility},
          {"frequency_hz", frequency_hz},
          {"modulation", modulation},
          {"luminance_cd_m2", luminance_cd_m2},
          {"worst_region_centre_deg", {x_deg, y_deg}},
          {"worst_region_size_deg", {region_w_deg, region_h_deg}},
          {"cff_hz", cff_hz},
          {"checked", what},
          {"model", "Barten's temporal CSF, the high-frequency fit of Bozorgian, Ashraf and Mantiuk (2024)"}};
}

}  // namespace layerlab

#include "layerlab/analysis/tolerance_spec.h"

#include <cmath>

#include "layerlab/framework/json_file.h"
#include "layerlab/framework/params.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

struct KindInfo {
  const char* key;
  Dimension dimension;
  double most;  // SI: the largest limit that is still an assembly tolerance
  const char* most_text;
  bool calibrated;
  const char* calibration;
};

const KindInfo& Info(ToleranceKind kind) {
  static const KindInfo infos[kToleranceKinds] = {
      {"panel_decentre", Dimension::kLength, 0.01, "10 mm", true, "yes: the fit's panel offsets (offset_x, offset_y)"},
      {"panel_tilt", Dimension::kAngle, 0.2, "0.2 rad (11.5 deg)", false,
       "no: the marker model is first order (a panel square to the axis); the fit refuses a tilted panel"},
      {"lens_decentre", Dimension::kLength, 0.01, "10 mm", false,
       "no: the fit has no lens decentre (a decentred lens shows as panel offsets it cannot tell apart)"},
      {"lens_tilt", Dimension::kAngle, 0.2, "0.2 rad (11.5 deg)", false, "no: the fit has no lens tilt"},
      {"gap", Dimension::kLength, 0.01, "10 mm", true,
       "yes: the panel distances, and a lens's gap (fitted when two camera positions see parallax)"},
      {"focal_length", Dimension::kFraction, 0.5, "50 %", true,
       "yes, when markers are seen from two camera positions (parallax); for a lens described by its surfaces no: "
       "the fit traces them, and a lens other than they say shows as a model error"},
  };
  return infos[static_cast<int>(kind)];
}

}  // namespace

std::string ToleranceKey(ToleranceKind kind) { return Info(kind).key; }
std::string CalibrationMeasures(ToleranceKind kind) { return Info(kind).calibration; }
bool CalibrationCanMeasure(ToleranceKind kind) { return Info(kind).calibrated; }

ToleranceSpec ReadToleranceSpec(const nlohmann::json& object, const Location& where) {
  if (!object.is_object())
    throw Error(where,
                "expected an object of tolerances (\"panel_decentre\": \"0.05 mm\", ...), got " + JsonKindName(object));
  Params p(object, where);
  ToleranceSpec spec;
  spec.source = where.file + (where.pointer.empty() ? "" : ": " + where.pointer);
  for (int k = 0; k < kToleranceKinds; ++k) {
    const ToleranceKind kind = static_cast<ToleranceKind>(k);
    const KindInfo& info = Info(kind);
    const std::optional<double> limit = p.optional_quantity(info.key, info.dimension);
    if (!limit) continue;
    if (!(*limit >= 0))
      p.fail(info.key,
             "a tolerance is a limit either way of the design, given positive; got " + object[info.key].dump());
    if (!(*limit <= info.most))
      p.fail(info.key, std::string("at most ") + info.most_text + " (an assembly tolerance, not a redesign); got " +
                           object[info.key].dump());
    spec.tolerances.push_back({kind, *limit});
  }
  p.check_all_read();
  if (spec.tolerances.empty())
    throw Error(where,
                "no tolerances: give at least one of panel_decentre, panel_tilt, lens_decentre, lens_tilt, "
                "gap, focal_length");
  return spec;
}

ToleranceSpec ReadToleranceFile(const std::string& path) {
  const nlohmann::json document = ReadJsonFile(path);
  return ReadToleranceSpec(document, Location{path, ""});
}

double DrawTruncatedNormal(Gaussian& random, double limit) {
  if (limit == 0) return 0;
  for (;;) {  // the draws beyond the limit (4.6 % of them) are redrawn
    const double x = 0.5 * limit * random();
    if (std::abs(x) <= limit) return x;
  }
}

}  // namespace layerlab

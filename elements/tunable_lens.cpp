// tunable_lens: a focus-tunable lens (liquid or liquid-crystal lens) whose power
// is set anew for each subframe of a time-multiplexed display, so that one
// panel behind it is imaged at a different depth in each subframe: the
// multifocal display. Its list has one entry per subframe of the scene's
// "subframes".
//
// | key            | type                  | default      | meaning                                       |
// |----------------|-----------------------|--------------|-----------------------------------------------|
// | powers         | [optical power, ...]  | one of the two | per subframe, "13.88 D"; 0 D is allowed (flat) |
// | focal_lengths  | [length, ...]         | one of the two | per subframe, nonzero                        |
// | clear_aperture | length                | unlimited    | diameter; a warning names the layers it vignettes |
// | gap            | length                | see thin_lens | path length from the element before it       |
// | next           | name                  | required     | the next element away from the eye            |
#include <cmath>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/framework/json_file.h"

namespace layerlab {
namespace {

constexpr size_t kMaxStates = 64;

class TunableLens final : public LensElement {
 public:
  TunableLens(std::vector<double> powers, std::optional<double> aperture)
      : powers_(std::move(powers)), aperture_(aperture) {}
  double focal_length() const override { return 1.0 / powers_[0]; }
  double power() const override { return powers_[0]; }
  std::optional<double> clear_aperture() const override { return aperture_; }
  bool tunable() const override { return true; }
  double power_in_subframe(int k) const override { return powers_[k]; }
  int powers_given() const override { return static_cast<int>(powers_.size()); }

 private:
  std::vector<double> powers_;
  std::optional<double> aperture_;
};

std::unique_ptr<Element> MakeTunableLens(Params& p) {
  const bool by_power = p.has("powers"), by_length = p.has("focal_lengths");
  if (by_power == by_length)
    p.fail(by_power ? "focal_lengths" : "powers",
           by_power ? "give either \"powers\" or \"focal_lengths\", not both"
                    : "missing key: give \"powers\" (one optical power per "
                      "subframe, e.g. [\"13.9 D\", \"12.0 D\"]) or \"focal_lengths\"");
  const std::string key = by_power ? "powers" : "focal_lengths";
  const nlohmann::json& list = p.raw(key);
  const Location at = p.where(key);
  if (!list.is_array() || list.empty() || list.size() > kMaxStates)
    throw Error(at, "expected a list of 1 to " + std::to_string(kMaxStates) + " values, one per subframe");
  std::vector<double> powers;
  for (size_t i = 0; i < list.size(); ++i) {
    const Location item = at.child(i);
    double v = 0;
    try {
      if (list[i].is_number())
        v = list[i].get<double>();
      else if (list[i].is_string())
        v = ParseQuantity(list[i].get<std::string>(), by_power ? Dimension::kOpticalPower : Dimension::kLength);
      else
        throw Error("expected " + std::string(by_power ? "an optical power" : "a length") + ", got " +
                    JsonKindName(list[i]));
    } catch (const Error& e) {
      throw Error(item, e.message());
    }
    if (!std::isfinite(v)) throw Error(item, "must be finite");
    if (!by_power && v == 0) throw Error(item, "a focal length of 0 would be infinite power");
    const double power = by_power ? v : 1.0 / v;
    if (std::abs(power) > 1000) throw Error(item, "more than 1000 D of power (a focal length under 1 mm)");
    powers.push_back(power);
  }
  std::optional<double> aperture = p.optional_quantity("clear_aperture", Dimension::kLength);
  if (aperture) p.require_range("clear_aperture", *aperture, 0.0, 10.0, true, false);
  return std::make_unique<TunableLens>(std::move(powers), aperture);
}

}  // namespace

ElementType TunableLensType() {
  return {"tunable_lens", ElementKind::kLens, "focus-tunable lens, one power per subframe", MakeTunableLens};
}

}  // namespace layerlab

// A new element type registered from inside a test, and a scene built with it.
#include "layerlab/elements/registry.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::Close;
using testing::ElementNamed;
using testing::ReadExample;

class NeutralDensityFilter final : public InlineOpticElement {
 public:
  explicit NeutralDensityFilter(double t) : t_(t) {}
  void transfer(Light& light) const override {
    for (ChannelLight& c : light) c.attenuate(t_);
  }

 private:
  double t_;
};

ElementType NeutralDensityType() {
  return {"nd_filter", ElementKind::kInlineOptic, "neutral density filter", [](Params& p) {
            double t = p.fraction_rgb("transmittance")[1];
            return std::make_unique<NeutralDensityFilter>(t);
          }};
}

TEST(Registry, ANewElementTypeJoinsTheScene) {
  ElementRegistry registry = ElementRegistry::WithBuiltins();
  registry.add(NeutralDensityType());
  nlohmann::json scene = ReadExample("multiplicative_2layer.json");
  ElementNamed(scene, "lens")["next"] = "nd";
  scene["elements"].push_back({{"type", "nd_filter"}, {"name", "nd"}, {"transmittance", 0.25}, {"next", "front"}});
  DisplaySystem s = testing::CompileJson(scene, registry);
  EXPECT_TRUE(Close(s.branches[0].optics_efficiency[1], 0.25, 1e-12));
  EXPECT_TRUE(Close(s.luminance_efficiency, 0.25 * 0.09, 1e-12));
}

TEST(Registry, UnknownTypesListTheRegisteredOnes) {
  ElementRegistry registry = ElementRegistry::WithBuiltins();
  registry.add(NeutralDensityType());
  nlohmann::json scene = ReadExample("multiplicative_2layer.json");
  ElementNamed(scene, "lens")["type"] = "nd_filtr";
  try {
    testing::CompileJson(scene, registry);
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "scene.json: /elements/1/type: unknown element type \"nd_filtr\"; did you mean "
                 "\"nd_filter\"? Known types: backlight, eye, half_mirror, hwp, lc_panel, lens, lens_array, "
                 "linear_polarizer, mirror, "
                 "nd_filter, pbs, qwp, thin_lens, tunable_lens, world");
  }
}

TEST(Registry, NamesAreUnique) {
  ElementRegistry registry = ElementRegistry::WithBuiltins();
  try {
    registry.add(NeutralDensityType());
    registry.add(NeutralDensityType());
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "element type \"nd_filter\" is registered twice");
  }
}

}  // namespace
}  // namespace layerlab

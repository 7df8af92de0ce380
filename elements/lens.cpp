// lens: a real lens of glass surfaces (a thick singlet, an asphere, a Fresnel
// lens, a cemented doublet or a whole eyepiece), traced exactly per channel
// (lenses/). The surfaces are listed from the eye outward; the first one's
// vertex is the lens's place on the path, and the next element's "gap"
// counts from the last one's.
//
// | key            | type    | default   | meaning                                              |
// |----------------|---------|-----------|------------------------------------------------------|
// | surfaces       | array of surfaces | one of two | from the eye outward, 2 to 64 (see lens.surface) |
// | prescription   | path    | one of two | a Zemax .zmx file (the subset in docs/optics.md), relative to the scene file; its first surface faces the eye |
// | clear_aperture | length  | unlimited | diameter of every surface that gives none itself     |
// | tilt           | [angle, angle] | [0, 0] | the whole lens turned about x, then about y, through its first vertex (as mounted off true) |
// | decentre       | [length, length] | [0, 0] | the whole lens shifted across the axis, x right, y up |
// | gap            | length  | see thin_lens | path length to the first vertex from the element before it |
// | next           | name    | required  | the next element away from the eye                   |
//
// lens.surface: one surface of a lens, from the eye outward, and the medium after it.
//
// | key             | type        | default | meaning                                                |
// |-----------------|-------------|---------|--------------------------------------------------------|
// | radius          | length      | flat    | signed: positive when the centre of curvature lies farther from the eye |
// | conic           | number      | 0       | conic constant k (0 sphere, -1 paraboloid)             |
// | even_asphere_mm | array of numbers | none | A4, A6, ... (up to 8): sag terms in mm for r in mm, A4 r^4 + A6 r^6 + ... |
// | fresnel_pitch   | length      | none    | groove pitch: the profile folded onto a flat substrate |
// | clear_aperture  | length      | the lens's | diameter                                            |
// | material        | name        | "air"   | after the surface, a catalogue glass (docs/optics.md); the last surface's is air |
// | thickness       | length      | required | axial distance to the next surface's vertex; the last surface has none |
#include <cmath>
#include <filesystem>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"
#include "layerlab/framework/text_file.h"
#include "layerlab/lenses/glass_catalog.h"
#include "layerlab/lenses/lens_system.h"
#include "layerlab/lenses/paraxial.h"
#include "layerlab/lenses/zmx_format.h"

namespace layerlab {
namespace {

constexpr size_t kMaxSurfaces = 64;
constexpr size_t kMaxPrescriptionBytes = size_t(1) << 20;

std::unique_ptr<Element> Finish(Params& p, lenses::Prescription prescription, std::optional<double> aperture);

class Lens final : public LensElement {
 public:
  Lens(std::shared_ptr<const lenses::LensSystem> system, double efl_m, std::optional<double> aperture_m)
      : system_(std::move(system)), efl_m_(efl_m), aperture_m_(aperture_m) {}
  // At the helium d line, as catalogues quote it; the compile uses each channel's own wavelength.
  double focal_length() const override { return efl_m_; }
  std::optional<double> clear_aperture() const override { return aperture_m_; }
  std::shared_ptr<const lenses::LensSystem> lens_system() const override { return system_; }

 private:
  std::shared_ptr<const lenses::LensSystem> system_;
  double efl_m_;
  std::optional<double> aperture_m_;
};

lenses::PrescriptionSurface ReadSurface(Params& s, bool last) {
  lenses::PrescriptionSurface out;
  if (std::optional<double> r = s.optional_quantity("radius", Dimension::kLength)) {
    if (*r == 0) s.fail("radius", "a radius of 0 is no surface; leave \"radius\" out for a flat one");
    out.shape.curvature_per_m = 1.0 / *r;
  }
  if (s.has("conic")) {
    const nlohmann::json& k = s.raw("conic");
    if (!k.is_number() || !std::isfinite(k.get<double>())) s.fail("conic", "expected a number, got " + k.dump());
    out.shape.conic = k.get<double>();
  }
  if (s.has("even_asphere_mm")) {
    const nlohmann::json& terms = s.raw("even_asphere_mm");
    if (!terms.is_array() || terms.empty() || terms.size() > 8)
      s.fail("even_asphere_mm", "expected a list of 1 to 8 numbers (A4, A6, ... in mm), got " + terms.dump());
    for (size_t i = 0; i < terms.size(); ++i) {
      if (!terms[i].is_number() || !std::isfinite(terms[i].get<double>()))
        s.fail("even_asphere_mm", "term " + std::to_string(i) + " is not a number: " + terms[i].dump());
      // z_m = 1e-3 A (1e3 r_m)^p with p = 4, 6, ...: A_SI = A_mm 10^(3 p - 3).
      const int power = 4 + 2 * static_cast<int>(i);
      out.shape.even_asphere.push_back(terms[i].get<double>() * std::pow(10.0, 3 * power - 3));
    }
  }
  if (std::optional<double> pitch = s.optional_quantity("fresnel_pitch", Dimension::kLength)) {
    s.require_range("fresnel_pitch", *pitch, 0.0, 0.1, true, false);
    out.shape.fresnel_pitch_m = *pitch;
  }
  std::optional<double> aperture = s.optional_quantity("clear_aperture", Dimension::kLength);
  if (aperture) s.require_range("clear_aperture", *aperture, 0.0, 10.0, true, false);
  if (aperture) out.shape.semi_diameter_m = *aperture / 2;
  out.material = s.string("material", "air");
  if (last) {
    if (out.material != "air")
      s.fail("material",
             "the last surface leads back into air (the path goes on in air), not into \"" + out.material + "\"");
    if (s.has("thickness"))
      s.fail("thickness", "the last surface has no thickness: the next element's \"gap\" counts from its vertex");
  } else {
    out.thickness_m = s.quantity("thickness", Dimension::kLength);
    s.require_range("thickness", out.thickness_m, 0.0, 1.0, false, false);
  }
  s.check_all_read();
  return out;
}

// A .zmx prescription named relative to the scene file.
lenses::Prescription ReadPrescription(Params& p) {
  if (p.has("surfaces")) p.fail("prescription", "give the lens's \"surfaces\" or its \"prescription\", not both");
  const std::string name = p.string("prescription");
  const std::filesystem::path scene_folder = std::filesystem::path(p.where().file).parent_path();
  const std::string path = (scene_folder / name).string();
  lenses::Prescription prescription;
  try {
    prescription = lenses::ReadZmx(ReadFileText(path, kMaxPrescriptionBytes), path);
  } catch (const Error& e) {
    p.fail("prescription", e.what());
  }
  if (prescription.material_before != "air")
    p.fail("prescription",
           path + ": the lens starts in \"" + prescription.material_before + "\"; it must start in air");
  if (prescription.surfaces.size() > kMaxSurfaces)
    p.fail("prescription", path + ": more than " + std::to_string(kMaxSurfaces) + " surfaces");
  if (prescription.surfaces.size() < 2 || prescription.surfaces.back().material != "air")
    p.fail("prescription", path + ": the lens must hold at least two surfaces and end in air");
  return prescription;
}

std::unique_ptr<Element> MakeLens(Params& p) {
  std::optional<double> aperture = p.optional_quantity("clear_aperture", Dimension::kLength);
  if (aperture) p.require_range("clear_aperture", *aperture, 0.0, 10.0, true, false);
  if (p.has("prescription")) return Finish(p, ReadPrescription(p), aperture);
  const nlohmann::json& list = p.raw("surfaces");
  if (!list.is_array() || list.size() < 2 || list.size() > kMaxSurfaces)
    p.fail("surfaces", "expected a list of 2 to " + std::to_string(kMaxSurfaces) +
                           " surface objects, from the eye outward, got " + list.dump().substr(0, 80));
  lenses::Prescription prescription;
  for (size_t i = 0; i < list.size(); ++i) {
    const Location at = p.where("surfaces").child(i);
    if (!list[i].is_object()) throw Error(at, "expected a surface object, got " + list[i].dump().substr(0, 80));
    Params s(list[i], at);
    prescription.surfaces.push_back(ReadSurface(s, i + 1 == list.size()));
  }
  return Finish(p, std::move(prescription), aperture);
}

// The validated lens, as mounted, and its catalogue focal length; the lens's
// clear aperture on every surface that gives none.
std::unique_ptr<Element> Finish(Params& p, lenses::Prescription prescription, std::optional<double> aperture) {
  const std::string key = p.has("prescription") ? "prescription" : "surfaces";
  for (lenses::PrescriptionSurface& s : prescription.surfaces)
    if (aperture && !std::isfinite(s.shape.semi_diameter_m)) s.shape.semi_diameter_m = *aperture / 2;
  const std::array<double, 2> tilt = p.quantity_pair("tilt", Dimension::kAngle, {0.0, 0.0});
  const std::array<double, 2> decentre = p.quantity_pair("decentre", Dimension::kLength, {0.0, 0.0});
  for (int a = 0; a < 2; ++a) {
    if (!(std::abs(tilt[a]) < 0.5)) p.fail("tilt", "at most 0.5 rad (28.6 deg) either way, about each axis");
    if (!(std::abs(decentre[a]) <= 0.1)) p.fail("decentre", "at most 0.1 m either way");
  }
  if (tilt != std::array<double, 2>{0, 0} || decentre != std::array<double, 2>{0, 0}) {
    if (!prescription.placements.empty())
      p.fail(key, "the prescription places its own surfaces; give tilt and decentre there");
    prescription.placements.push_back(
        {0, static_cast<int>(prescription.surfaces.size()) - 1, tilt[0], tilt[1], decentre[0], decentre[1]});
  }
  auto system = std::make_shared<const lenses::LensSystem>(std::move(prescription), p.where(key));
  double efl = 0;
  try {
    efl = lenses::ParaxialAt(Centred(*system), lenses::kLineD_m).efl_m;
  } catch (const Error& e) {
    p.fail(key, e.message());
  }
  double smallest = INFINITY;
  for (int i = 0; i < system->size(); ++i)
    smallest = std::min(smallest, 2 * system->surface(i).shape().semi_diameter_m);
  return std::make_unique<Lens>(std::move(system), efl,
                                std::isfinite(smallest) ? std::optional<double>(smallest) : std::nullopt);
}

}  // namespace

lenses::LensSystem Centred(const lenses::LensSystem& system) {
  lenses::Prescription nominal = system.prescription();
  nominal.placements.clear();
  return lenses::LensSystem(std::move(nominal));
}

ElementType LensType() { return {"lens", ElementKind::kLens, "real lens of glass surfaces, traced exactly", MakeLens}; }

}  // namespace layerlab

// element: the keys every element object has, whatever its type; the
// registry reads them before the type's factory reads the rest.
//
// | key  | type         | default  | meaning                                                        |
// |------|--------------|----------|----------------------------------------------------------------|
// | type | element type | required | one of the types below                                         |
// | name | string       | required | unique in the scene; letters, digits, '_', '-', '.'; names output files |
#include "layerlab/elements/registry.h"

#include <cctype>

namespace layerlab {

std::string KindName(ElementKind kind) {
  switch (kind) {
    case ElementKind::kEye:
      return "an eye";
    case ElementKind::kLens:
      return "a lens";
    case ElementKind::kMirror:
      return "a mirror";
    case ElementKind::kCombiner:
      return "a combiner";
    case ElementKind::kInlineOptic:
      return "an in-line optic";
    case ElementKind::kPanel:
      return "a panel";
    case ElementKind::kBacklight:
      return "a backlight";
    case ElementKind::kWorld:
      return "the world";
  }
  return "an element";
}

void ElementRegistry::add(ElementType type) {
  if (type.name.empty() || !type.make) throw Error("an element type needs a name and a factory");
  std::string name = type.name;
  if (!types_.emplace(name, std::move(type)).second) throw Error("element type \"" + name + "\" is registered twice");
}

const ElementType* ElementRegistry::find(const std::string& name) const {
  auto it = types_.find(name);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> ElementRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, type] : types_) out.push_back(name);
  return out;
}

std::unique_ptr<Element> ElementRegistry::create(Params& params) const {
  std::string type_name = params.string("type");
  const ElementType* type = find(type_name);
  if (!type) {
    std::string msg = "unknown element type \"" + type_name + "\"";
    if (auto near = ClosestWord(type_name, names())) msg += "; did you mean \"" + *near + "\"?";
    msg += " Known types: " + JoinWords(names(), ", ");
    params.fail("type", msg);
  }
  std::string name = params.string("name");
  if (name.empty()) params.fail("name", "an element name must not be empty");
  for (unsigned char c : name)
    if (!(std::isalnum(c) || c == '_' || c == '-' || c == '.'))
      params.fail("name", "\"" + name + "\" may use only letters, digits, '_', '-' and '.'");
  std::optional<double> gap;
  // A backlight reads it only with a pattern (elements/backlight.cpp); the world has no place.
  if (type->kind != ElementKind::kEye && type->kind != ElementKind::kWorld) {
    gap = params.optional_quantity("gap", Dimension::kLength);
    if (gap && !(*gap > 0))
      params.fail(
          "gap", "the path length from the element before must be positive, got " + FormatFixed(*gap * 1e3, 3) + " mm");
    if (gap) params.require_range("gap", *gap, 0.0, 100.0, true, false);
  }
  std::unique_ptr<Element> element = type->make(params);
  if (element->kind() != type->kind)
    throw Error(params.where(), "element type \"" + type_name + "\" built " + KindName(element->kind()) +
                                    " but is registered as " + KindName(type->kind));
  element->type_ = type_name;
  element->name_ = name;
  element->where_ = params.where();
  element->gap_ = gap;
  return element;
}

}  // namespace layerlab

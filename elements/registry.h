// Element types by name. Built-ins are listed, one line each, in
// builtin_elements.def; tests and plug-ins may add their own at run time.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "layerlab/elements/element.h"

namespace layerlab {

// Reads its parameters (every key it understands) and returns the element;
// throws layerlab::Error naming the key on bad input.
using ElementFactory = std::function<std::unique_ptr<Element>(Params&)>;

struct ElementType {
  std::string name;  // the JSON "type"
  ElementKind kind;
  std::string summary;
  ElementFactory make;
};

class ElementRegistry {
 public:
  void add(ElementType type);  // fails if the name is taken
  const ElementType* find(const std::string& name) const;
  std::vector<std::string> names() const;

  // Builds an element from its JSON object: "type" and "name" are read here,
  // the rest by the factory; connection ports are left for the scene walker.
  std::unique_ptr<Element> create(Params& params) const;

  static ElementRegistry WithBuiltins();

 private:
  std::map<std::string, ElementType> types_;
};

}  // namespace layerlab

#include "layerlab/tools/scene_reference.h"

#include <map>

#include "layerlab/analysis/contrast_option_table.h"
#include "layerlab/analysis/run_option_table.h"
#include "layerlab/elements/registry.h"
#include "layerlab/framework/error.h"
#include "layerlab/solvers/solver_option_table.h"

namespace layerlab {
namespace {

struct Source {
  std::string file;                   // relative to the source folder
  std::vector<std::string> sections;  // the tables it must hold, in order
};

std::vector<Source> Sources() {
  std::vector<Source> sources = {{"systems/scene.cpp", {"scene"}}, {"elements/registry.cpp", {"element"}}};
  for (const std::string& type : ElementRegistry::WithBuiltins().names())
    sources.push_back({"elements/" + type + ".cpp", {type}});
  for (Source& s : sources)
    if (s.file == "elements/lens.cpp") s.sections.push_back("lens.surface");
  sources.push_back({"solvers/solver_option_table.cpp", {"solve"}});
  sources.push_back({"analysis/run_config.cpp", {"run", "run.retina", "run.contrast", "run.compare", "depth_range"}});
  return sources;
}

std::string Row(const std::vector<std::string>& cells) {
  std::string out = "|";
  for (const std::string& c : cells) out += " " + c + " |";
  return out + "\n";
}

std::string Code(const std::string& s) { return s.empty() ? "" : "`" + s + "`"; }

// A section made from an option table (framework/option_table.h): the
// scene's keys, then the options the scene file does not set.
KeyTable OptionKeyTable(const std::string& section, const std::string& file, const std::string& prose,
                        const std::vector<const OptionSpec*>& entries) {
  KeyTable t;
  t.section = section;
  t.file = file;
  t.from_option_table = true;
  t.prose = prose;
  for (const OptionSpec* e : entries) {
    KeyRow r{e->key, e->type, e->default_text, e->meaning, "", "", ""};
    if (e->has_range) r.range = e->range.Text(e->kind == OptionKind::kInteger) + e->constraint_note;
    if (e->kind == OptionKind::kSeed) r.range = "[0, 2^64 - 1]";
    r.cli_flag = e->cli_flag;
    r.python = e->python;
    (e->in_scene ? t.rows : t.other_options).push_back(r);
  }
  return t;
}

// The sections made from option tables, by name.
std::map<std::string, KeyTable> OptionTables() {
  std::map<std::string, KeyTable> out;
  out["solve"] = OptionKeyTable(
      "solve", "solvers/solver_option_table.cpp",
      "the scene's \"solve\" section, the solver and its target; the command line (`layerlab solve`) and Python's "
      "`solve()` override any of it. Paths are relative to the scene file's folder. A key of an option that the "
      "chosen solver does not read is refused. A value outside its range is refused, by the scene reader, the "
      "command line and Python alike (SolverOptions::IsValid).",
      OptionSpecs(SolverOptionTable()));
  out["run"] = OptionKeyTable(
      "run", "analysis/run_option_table.cpp",
      "the scene's \"run\" section, what `layerlab run` does beyond the solve (docs/run-section.md). Nothing that "
      "is not declared is computed.",
      OptionSpecs(RunOptionTable()));
  out["run.retina"] =
      OptionKeyTable("run.retina", "analysis/run_option_table.cpp",
                     "retinal images over accommodation (needs a target).", OptionSpecs(RetinaRunOptionTable()));
  out["run.compare"] =
      OptionKeyTable("run.compare", "analysis/run_option_table.cpp",
                     "other displays on the same target (needs a target).", OptionSpecs(CompareRunOptionTable()));
  out["run.frames"] = OptionKeyTable(
      "run.frames", "analysis/run_option_table.cpp",
      "a moving target scene (\"solve\": {\"target_scene\": ...} with keys, docs/target-format.md) solved frame "
      "by frame, each frame from the one before, as `layerlab solve --frames` does; into OUT/frames.",
      OptionSpecs(FramesRunOptionTable()));
  out["run.contrast"] = OptionKeyTable(
      "run.contrast", "analysis/contrast_option_table.cpp",
      "normalized contrast against accommodation (the paper's Fig. 5); needs no target: each display is factorized "
      "for a cosine grating at each depth. `layerlab contrast` and Python's `contrast()` take the same options. A "
      "value outside its range is refused, by the scene reader, the command line and Python alike "
      "(ContrastOptions::IsValid).",
      OptionSpecs(ContrastOptionTable()));
  return out;
}

std::string OptionTableRows(const std::vector<KeyRow>& rows) {
  std::string md = Row({"key", "type", "unit", "range", "default", "meaning", "command line", "Python"});
  md += "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const KeyRow& r : rows)
    md += Row({Code(r.key), r.type, UnitsOfType(r.type), r.range, r.default_value, r.meaning, Code(r.cli_flag),
               Code(r.python)});
  return md;
}

}  // namespace

std::vector<KeyTable> SceneReferenceTables(const std::string& source_dir) {
  std::vector<KeyTable> out;
  const std::map<std::string, KeyTable> option_tables = OptionTables();
  for (const Source& source : Sources()) {
    std::map<std::string, KeyTable> by_section;
    bool commented = false;
    for (const std::string& section : source.sections) commented = commented || !option_tables.count(section);
    if (commented)
      for (KeyTable& t : ReadKeyTables(source_dir + "/" + source.file)) {
        t.file = source.file;
        by_section[t.section] = t;
      }
    for (const std::string& section : source.sections) {
      if (auto made = option_tables.find(section); made != option_tables.end()) {
        out.push_back(made->second);
        continue;
      }
      auto it = by_section.find(section);
      if (it == by_section.end())
        throw Error(source.file + ": no key table \"" + section + ": ...\" in the leading comment");
      out.push_back(it->second);
    }
  }
  return out;
}

std::string SceneReferenceMarkdown(const std::string& source_dir) {
  std::string md =
      "# Scene file reference\n\n"
      "<!-- Generated by tools/scene_reference from the key tables at the top of the source files named below;\n"
      "     do not edit: change the table in the source and run `cmake --build build --target scene-reference`.\n"
      "     The test docs.scene_reference_current fails when this file is not what the tables make, and\n"
      "     reference_tests fails when a table and the keys its code reads differ. -->\n\n"
      "Every key of a scene file (`layerlab-scene/1`): the top level, every element type, and the `solve` and\n"
      "`run` sections. A quantity is a string with its unit (`\"75 mm\"`, `\"0.4 D\"`, `\"36 deg\"`) or a bare\n"
      "JSON number in SI units (meters, radians, diopters, cd/m2, seconds); a depth needs its unit. A key that is\n"
      "not listed is an error that names the closest listed one; so is a required key left out.\n\n";
  std::vector<KeyTable> tables = SceneReferenceTables(source_dir);
  bool types_begun = false;
  const ElementRegistry registry = ElementRegistry::WithBuiltins();
  for (const KeyTable& t : tables) {
    const bool element_type = registry.find(t.section) != nullptr;
    if (element_type && !types_begun) {
      md += "## Element types\n\n";
      types_begun = true;
    }
    md += std::string(element_type ? "### " : "## ") + Code(t.section) + "\n\n";
    md += t.prose + "\n\n";
    if (t.from_option_table) {
      md += "Described in " + Code(t.file) + ".\n\n" + OptionTableRows(t.rows) + "\n";
      if (!t.other_options.empty())
        md += "Options the scene file does not set:\n\n" + OptionTableRows(t.other_options) + "\n";
      continue;
    }
    md += "Read in " + Code(t.file) + ".\n\n";
    md += Row({"key", "type", "unit", "default", "meaning"});
    md += "| --- | --- | --- | --- | --- |\n";
    for (const KeyRow& r : t.rows) {
      std::string units = UnitsOfType(r.type);
      md += Row({Code(r.key), r.type, units.empty() ? "" : units, r.default_value, r.meaning});
    }
    md += "\n";
  }
  return md;
}

}  // namespace layerlab

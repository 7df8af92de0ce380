#include "layerlab/solvers/solver_checkpoint.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/content_digest.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/solvers/trace_columns.h"
#include "layerlab/systems/system_report.h"

namespace layerlab {
namespace fs = std::filesystem;

namespace {

std::string PatternName(const VirtualLayer& layer, int iteration) {
  return layer.name + "-iteration" + std::to_string(iteration) + ".exr";
}

// A trace row as an array in the order of TraceColumns(): a count as an
// integer, an infinite value as "inf" or "-inf", an unmeasured one as null.
nlohmann::json CheckpointTraceRow(const IterationRecord& r) {
  nlohmann::json row = nlohmann::json::array();
  for (const TraceColumn& c : TraceColumns()) row.push_back(TraceJson(c, r));
  return row;
}

// The row back. Checkpoints written before a column existed lack it: every
// column after the first four may be missing, and is then NaN.
IterationRecord TraceRecordOf(const nlohmann::json& row) {
  IterationRecord r;
  const std::vector<TraceColumn>& columns = TraceColumns();
  for (size_t k = 0; k < columns.size(); ++k) {
    if (k >= 4 && k >= row.size()) {
      columns[k].set(&r, std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const nlohmann::json& v = row.at(k);
    if (v.is_string())
      columns[k].set(&r, v.get<std::string>() == "-inf" ? -INFINITY : INFINITY);
    else if (v.is_null())
      columns[k].set(&r, std::numeric_limits<double>::quiet_NaN());
    else if (columns[k].kind == TraceValueKind::kCount)
      columns[k].set(&r, v.get<int>());
    else
      columns[k].set(&r, v.get<double>());
  }
  return r;
}

}  // namespace

void WriteCheckpoint(const DisplayModel& model, const SolverCheckpoint& c, const std::string& folder,
                     const CheckpointInputs& inputs) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw Error(folder + ": cannot create the checkpoint folder: " + ec.message());
  nlohmann::json files = nlohmann::json::object();
  for (size_t k = 0; k < model.layer_count(); ++k) {
    const VirtualLayer& layer = model.system().layers[k];
    const std::string name = PatternName(layer, c.iteration);
    WriteExr((fs::path(folder) / name).string(),
             Image{c.patterns[k].cols, c.patterns[k].rows, {"R", "G", "B"}, c.patterns[k].rgb});
    files[layer.name] = name;
  }
  nlohmann::json trace = nlohmann::json::array();
  for (const IterationRecord& r : c.trace) trace.push_back(CheckpointTraceRow(r));
  nlohmann::json doc = {{"format", "layerlab-checkpoint/1"},
                        {"solver", c.solver},
                        {"iteration", c.iteration},
                        {"seconds", c.seconds},
                        {"patterns", files},
                        {"state", c.state},
                        {"trace", trace},
                        {"digest", inputs}};
  WriteFileAtomically((fs::path(folder) / "checkpoint.json").string(), doc.dump(1) + "\n");
  // The new checkpoint is complete: the old pattern files can go.
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 4 && name.ends_with(".exr") && name.find("-iteration") != std::string::npos &&
        name.find("-iteration" + std::to_string(c.iteration) + ".exr") == std::string::npos)
      fs::remove(entry.path(), ec);
  }
}

SolverCheckpoint ReadCheckpoint(const DisplayModel& model, const std::string& folder) {
  const std::string file = (fs::path(folder) / "checkpoint.json").string();
  nlohmann::json doc = ReadJsonFile(file);
  SolverCheckpoint c;
  try {
    if (doc.at("format") != "layerlab-checkpoint/1") throw Error(file + ": /format: not a layerlab-checkpoint/1 file");
    c.solver = doc.at("solver").get<std::string>();
    c.iteration = doc.at("iteration").get<int>();
    c.seconds = doc.at("seconds").get<double>();
    for (const auto& [key, value] : doc.at("state").items()) c.state[key] = value.get<double>();
    for (const auto& row : doc.at("trace")) c.trace.push_back(TraceRecordOf(row));
    if (c.iteration < 0 || c.trace.empty() || c.trace.back().iteration != c.iteration)
      throw Error(file + ": /trace does not end at /iteration " + std::to_string(c.iteration));
    for (size_t k = 0; k < model.layer_count(); ++k) {
      const VirtualLayer& layer = model.system().layers[k];
      if (!doc.at("patterns").contains(layer.name))
        throw Error(file + ": /patterns: no pattern for layer \"" + layer.name +
                    "\" (a checkpoint of another display?)");
      const std::string name = doc["patterns"][layer.name].get<std::string>();
      if (name.find('/') != std::string::npos || name.find("..") != std::string::npos)
        throw Error(file + ": /patterns/" + layer.name + ": \"" + name +
                    "\" must be a file name in the checkpoint folder");
      Image image = ReadExr((fs::path(folder) / name).string(), {"R", "G", "B"});
      if (image.width != layer.cols || image.height != layer.rows)
        throw Error((fs::path(folder) / name).string() + ": " + std::to_string(image.width) + " x " +
                    std::to_string(image.height) + " pixels; layer \"" + layer.name + "\" has " +
                    std::to_string(layer.cols) + " x " + std::to_string(layer.rows));
      for (float v : image.pixels)
        if (!(v >= 0.0f && v <= 1.0f))
          throw Error((fs::path(folder) / name).string() + ": a transmittance outside [0, 1]");
      LayerPattern p(layer.cols, layer.rows, 0);
      p.rgb = std::move(image.pixels);
      c.patterns.push_back(std::move(p));
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(file + ": not a valid checkpoint: " + e.what());
  }
  return c;
}

CheckpointInputs CheckpointDigest(const DisplayModel& model, Sampling sampling, const LightField& target,
                                  const std::string& solver, const SolverOptions& o) {
  char text[256];
  std::snprintf(text, sizeof text,
                "sub_iterations=%d warm_start=%d seed=%llu initial=%.17g epsilon=%.17g floor=%.17g range=%d",
                o.sub_iterations, o.warm_start_iterations, static_cast<unsigned long long>(o.seed), o.initial_value,
                o.epsilon, o.floor, static_cast<int>(o.target_range));
  std::string options = std::string(text) + " objective=" + ToString(o.objective);
  if (o.panel_diffraction) {  // and what it depends on beyond the system's geometry
    options += " panel_diffraction=1";
    for (const VirtualLayer& layer : model.system().layers) {
      std::snprintf(text, sizeof text, " fill=%.17g,%.17g", layer.panel.fill_factor[0], layer.panel.fill_factor[1]);
      options += text;
    }
    for (const Branch& branch : model.system().branches) {
      std::snprintf(text, sizeof text, " coherence=%.17g", branch.backlight_coherence_width_m);
      options += text;
    }
  }
  if (o.lc_response) {  // and the response it solves through
    options += " lc_response=1";
    std::snprintf(text, sizeof text, " frame_rate=%.17g", model.system().frame_rate_hz);
    options += text;
    for (const VirtualLayer& layer : model.system().layers) {
      std::snprintf(text, sizeof text, " response=%.17g,%.17g", layer.panel.rise_time_s, layer.panel.fall_time_s);
      options += text;
    }
  }
  if (o.objective == ObjectiveKind::kRetinal) {  // what the retinal objective minimizes
    auto list = [](const std::vector<double>& values) {
      std::string s;
      for (double v : values) {
        char number[32];
        std::snprintf(number, sizeof number, "%.17g", v);
        s += (s.empty() ? "" : ",") + std::string(number);
      }
      return s;
    };
    std::snprintf(text, sizeof text, " resolution=%.17g target=%d contrast_sensitivity=%d", o.retinal.resolution_rad,
                  static_cast<int>(o.retinal.target), o.retinal.contrast_sensitivity ? 1 : 0);
    options += " states=" + list(o.retinal.states_diopters) + " weights=" + list(o.retinal.weights) + text;
  }
  return {{"display", ContentDigest().add(SystemToJson(model.system()).dump()).add(&sampling, sizeof sampling).hex()},
          {"target", LightFieldDigest(target)},
          {"solver", solver},
          {"options", options}};
}

void RefuseMismatchedCheckpoint(const std::string& folder, const CheckpointInputs& now) {
  const std::string file = (fs::path(folder) / "checkpoint.json").string();
  CheckpointInputs recorded;
  const nlohmann::json doc = ReadJsonFile(file);
  if (doc.contains("digest") && doc["digest"].is_object())
    for (const auto& [key, value] : doc["digest"].items())
      if (value.is_string()) recorded[key] = value.get<std::string>();
  if (recorded.empty())
    throw Error(file +
                ": /digest: the checkpoint does not record what it was made for (an older layerlab); "
                "it cannot be resumed safely. Nothing was written");
  static const std::map<std::string, std::string> names = {{"display", "display (scene or sampling)"},
                                                           {"target", "target"},
                                                           {"solver", "solver"},
                                                           {"options", "solver options"}};
  for (const auto& [key, value] : now) {
    auto it = recorded.find(key);
    if (it == recorded.end() || it->second != value)
      throw Error(file + ": /digest/" + key + ": the checkpoint was made for another " + names.at(key) + " (" +
                  (it == recorded.end() ? std::string("none recorded") : it->second) + "; this run: " + value +
                  "); resume with the same inputs or start afresh without --resume. Nothing was written");
  }
}

}  // namespace layerlab

// A rendered target kept in a run's output folder (OUT/target/lightfield and
// OUT/target/render.json), so that the next run whose target scene has not
// changed reads the render instead of tracing it again.
//
// The key is a content digest of the target scene file, every file it reads
// (meshes, images: TargetScene::files_read), the light field's geometry (which
// may come from the display named by "display") and kTargetRenderVersion.
// render.json records the key and the digest of the rendered values, which is
// checked when the light field is read back. The render is kept in the run's
// staging folder and switched into place with the rest of the run
// (framework/staged_output.h), so a render that is killed or fails leaves
// nothing that a later run would reuse.
#pragma once

#include <optional>
#include <string>

#include "layerlab/framework/lightfield.h"
#include "layerlab/targets/target_scene.h"

namespace layerlab {

inline constexpr const char* kRenderRecordFormat = "layerlab-target-render/1";
// Part of the key: raise it when the renderer's output changes for the same scene.
inline constexpr int kTargetRenderVersion = 1;

// The key of a target scene's render (16 hex digits); reads the scene file
// and every file it read again.
std::string TargetSceneDigest(const TargetScene& scene);

// The light field rendered for `digest` in `folder` (a run's target/), or
// nothing, with why not in *why_not (no earlier render, another scene or
// geometry, unreadable, values changed since written).
std::optional<LightField> ReadCachedRender(const std::string& folder, const std::string& digest, std::string* why_not);

// Keeps `lf`, the render of `scene` for `digest`, in `folder`: the light field
// in folder/lightfield and its record in folder/render.json (written last).
// With `reuse_from` (a folder ReadCachedRender read `lf` from), its files are
// hard-linked (copied where links fail) instead of written again.
void KeepRender(const LightField& lf, const TargetScene& scene, const std::string& digest, const std::string& folder,
                const std::string& reuse_from = "");

}  // namespace layerlab

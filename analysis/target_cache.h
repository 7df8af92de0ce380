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
//
// Runs that share a store (a sweep's jobs: DIR/targets) also keep each render
// there by its key, STORE/<key>/, so that of the jobs whose target scene is
// the same only the first renders it; the others wait for it on
// STORE/<key>.lock and link its files.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "layerlab/framework/file_lock.h"

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

// Where the render for `digest` is kept in a shared store: STORE/<digest>.
std::string SharedRenderFolder(const std::string& store, const std::string& digest);

// Holds STORE/<digest>.lock, waiting while another process holds it (that one
// renders the same scene); `waiting` is told once who holds it. Throws
// InterruptedError when Ctrl-C arrives while waiting.
FileLock LockSharedRender(const std::string& store, const std::string& digest,
                          const std::function<void(const std::string& holder)>& waiting);

// Puts the render KeepRender kept in `kept` into the store under `digest`,
// hard-linked, switched into place whole (a partial copy of a killed process
// is replaced). Call it holding LockSharedRender.
void ShareRender(const std::string& kept, const std::string& store, const std::string& digest);

}  // namespace layerlab

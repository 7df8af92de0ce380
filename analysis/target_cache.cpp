#include "layerlab/analysis/target_cache.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>
#include <vector>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/content_digest.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/file_read_observer.h"
#include "layerlab/framework/interrupt.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/lightfield_io.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

// The file's size, then its bytes' digest: two files cannot run into each other.
void AddBytes(ContentDigest& digest, const FileBytes& bytes) {
  digest.add(&bytes.size, sizeof bytes.size).add(&bytes.digest, sizeof bytes.digest);
}

FileBytes BytesOfFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open for reading (to key the target's render)");
  AnnounceFileRead(path);
  std::vector<char> buffer(1 << 16);
  ContentDigest bytes;
  uint64_t size = 0;
  while (in.read(buffer.data(), static_cast<std::streamsize>(buffer.size())) || in.gcount() > 0) {
    bytes.add(buffer.data(), static_cast<size_t>(in.gcount()));
    size += static_cast<uint64_t>(in.gcount());
  }
  return {size, bytes.value()};
}

// The file `from` hard-linked (or copied, where links fail) to `at`.
void LinkFile(const fs::path& from, const fs::path& at, std::error_code& ec) {
  fs::create_directories(at.parent_path(), ec);
  std::error_code link_ec;
  fs::create_hard_link(from, at, link_ec);
  if (link_ec) fs::copy_file(from, at, fs::copy_options::overwrite_existing, ec);
}

// Every file under `from`, hard-linked (or copied) to the same place under `to`.
void LinkTree(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(from, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    const fs::path at = to / it->path().lexically_relative(from);
    if (it->is_directory())
      fs::create_directories(at, ec);
    else
      LinkFile(it->path(), at, ec);
    if (ec) break;
  }
  if (ec) throw Error(to.string() + ": cannot keep the earlier render (" + ec.message() + ")");
}

}  // namespace

std::string TargetSceneDigest(const TargetScene& scene) {
  ContentDigest digest;
  const int version = kTargetRenderVersion;
  digest.add(&version, sizeof version);
  AddGeometry(digest, scene.geometry);
  if (scene.moved_m != std::array<double, 3>{0, 0, 0}) {  // unmoved scenes keep their keys
    const char tag[] = "moved";
    digest.add(tag, sizeof tag);
    digest.add(scene.moved_m.data(), sizeof scene.moved_m);
  }
  if (scene.animation) {  // a moving scene's every frame has its own key; still scenes keep theirs
    const char tag[] = "time";
    digest.add(tag, sizeof tag);
    digest.add(&scene.time_s, sizeof scene.time_s);
  }
  if (scene.file_bytes)
    AddBytes(digest, *scene.file_bytes);
  else
    AddBytes(digest, BytesOfFile(scene.file));
  // A file the scene names twice (one mesh placed twice) is read once and added twice.
  std::map<std::string, FileBytes> read;
  for (const std::string& file : scene.files_read) {
    auto [at, first] = read.try_emplace(file);
    if (first) at->second = BytesOfFile(file);
    AddBytes(digest, at->second);
  }
  return digest.hex();
}

std::optional<LightField> ReadCachedRender(const std::string& folder, const std::string& digest, std::string* why_not) {
  const fs::path record_file = fs::path(folder) / "render.json";
  std::error_code ec;
  if (!fs::exists(record_file, ec)) {
    *why_not = "no earlier render in " + folder;
    return std::nullopt;
  }
  try {
    const nlohmann::json record = ReadJsonFile(record_file.string());
    if (!record.is_object() || record.value("format", "") != kRenderRecordFormat)
      throw Error(record_file.string() + ": not a " + kRenderRecordFormat + " record");
    const std::string recorded = record.value("digest", "");
    if (recorded != digest) {
      *why_not = "the target scene, a file it reads or its geometry changed since the render in " + folder + " (key " +
                 recorded + ", now " + digest + ")";
      return std::nullopt;
    }
    LightField lf = ReadLightField((fs::path(folder) / "lightfield").string(), {.load_depth = false});
    if (LightFieldDigest(lf) != record.value("light_field_digest", "")) {
      *why_not = "the render in " + folder + " was changed after it was written";
      return std::nullopt;
    }
    return lf;
  } catch (const Error& e) {
    *why_not = "the render in " + folder + " cannot be used (" + e.message() + ")";
  } catch (const nlohmann::json::exception& e) {
    *why_not = "the render in " + folder + " cannot be used (" + e.what() + ")";
  }
  return std::nullopt;
}

void KeepRender(const LightField& lf, const TargetScene& scene, const std::string& digest, const std::string& folder,
                const std::string& reuse_from) {
  const fs::path dir(folder);
  if (reuse_from.empty())
    WriteLightField(lf, (dir / "lightfield").string());
  else
    LinkTree(fs::path(reuse_from) / "lightfield", dir / "lightfield");
  const LightFieldGeometry& g = lf.geometry;
  std::vector<std::string> files;
  for (const std::string& f : scene.files_read) files.push_back(fs::path(f).lexically_normal().string());
  const nlohmann::json record = {
      {"format", kRenderRecordFormat},
      {"digest", digest},
      {"renderer_version", kTargetRenderVersion},
      {"target_scene", scene.file},
      {"files_read", files},
      {"geometry", std::to_string(g.views_x) + " x " + std::to_string(g.views_y) + " views of " +
                       std::to_string(g.cols) + " x " + std::to_string(g.rows) + " pixels"},
      {"light_field_digest", LightFieldDigest(lf)}};
  WriteFileAtomically((dir / "render.json").string(), record.dump(2) + "\n");
}

std::string SharedRenderFolder(const std::string& store, const std::string& digest) {
  return (fs::path(store) / digest).string();
}

FileLock LockSharedRender(const std::string& store, const std::string& digest,
                          const std::function<void(const std::string& holder)>& waiting) {
  std::error_code ec;
  fs::create_directories(store, ec);
  if (ec) throw Error(store + ": cannot create the folder of shared target renders (" + ec.message() + ")");
  const std::string path = SharedRenderFolder(store, digest) + ".lock";
  bool told = false;
  for (;;) {
    std::string holder;
    if (std::optional<FileLock> lock = FileLock::TryLock(path, &holder)) return std::move(*lock);
    if (!told && waiting) waiting(holder.empty() ? "another process" : holder);
    told = true;
    if (Interrupted()) throw InterruptedError("interrupted while waiting for " + path);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

void ShareRender(const std::string& kept, const std::string& store, const std::string& digest) {
  const fs::path done = SharedRenderFolder(store, digest), partial = done.string() + ".partial";
  std::error_code ec;
  fs::remove_all(partial, ec);
  LinkTree(fs::path(kept) / "lightfield", partial / "lightfield");
  LinkFile(fs::path(kept) / "render.json", partial / "render.json", ec);
  if (ec) throw Error(partial.string() + ": cannot keep the target's render there (" + ec.message() + ")");
  fs::remove_all(done, ec);  // an earlier render that could not be used; the lock keeps readers out
  fs::rename(partial, done, ec);
  if (ec) throw Error(done.string() + ": cannot keep the target's render there (" + ec.message() + ")");
}

}  // namespace layerlab

// The file system around a light-field folder: the input bytes build a random
// tree under a scratch folder (views that are good EXRs, truncated ones,
// FIFOs, sockets, folders, links that loop, dangle, point at a device or out
// of the folder, extra entries with digit names of any length, links for the
// views/ folder and the manifest), then ReadLightField reads it. Refusing with
// layerlab::Error is fine; anything else (another exception, a crash, a
// sanitizer report, a FIFO that blocks: libFuzzer's timeout) is a finding.
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/fuzz/fuzz_util.h"

namespace {

namespace fs = std::filesystem;

constexpr const char* kManifest = R"({"format": "lightfield/1", "origin_plane_z": 0.5,
  "window": {"left": -0.1, "top": 0.1, "width": 0.2, "height": 0.2},
  "resolution": {"cols": 2, "rows": 2},
  "views": {"rows": 2, "cols": 2, "eyebox_width": 0.004, "eyebox_height": 0.004},
  "views_pattern": "views/r{row:02}_c{col:02}.exr"})";

struct Bytes {
  const uint8_t* data;
  size_t size, at = 0;
  uint8_t next() { return at < size ? data[at++] : 0; }
};

void MakeSocket(const fs::path& p) {
  const int s = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (s >= 0 && p.string().size() < sizeof address.sun_path) {
    std::snprintf(address.sun_path, sizeof address.sun_path, "%s", p.c_str());
    (void)bind(s, reinterpret_cast<sockaddr*>(&address), sizeof address);
  }
  if (s >= 0) close(s);
}

// One entry at `p`, of the kind the next byte picks.
void MakeEntry(Bytes& in, const fs::path& p, const fs::path& good, const fs::path& outside) {
  std::error_code ec;
  switch (in.next() % 10) {
    case 0:
    case 1:
      fs::copy_file(good, p, ec);
      break;
    case 2: {  // truncated at a byte-chosen length
      const auto bytes = fs::file_size(good, ec);
      fs::copy_file(good, p, ec);
      if (!ec && bytes > 0) fs::resize_file(p, in.next() % bytes, ec);
      break;
    }
    case 3:
      mkfifo(p.c_str(), 0600);
      break;
    case 4:
      MakeSocket(p);
      break;
    case 5:
      fs::create_directory(p, ec);
      break;
    case 6:
      fs::create_symlink(p.filename(), p, ec);
      break;  // loops
    case 7:
      fs::create_symlink("no_such_file.exr", p, ec);
      break;
    case 8:
      fs::create_symlink(in.next() % 2 ? "/dev/zero" : outside.c_str(), p, ec);
      break;
    default:
      break;  // missing
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path scratch = layerlab::fuzz::ScratchDir();
  const fs::path good = scratch / "good.exr", outside = scratch / "outside.exr";
  static const bool once = [&] {
    layerlab::WriteExr(good.string(), layerlab::Image{2, 2, {"R", "G", "B"}, std::vector<float>(12, 0.25f)});
    fs::copy_file(good, outside);
    return true;
  }();
  (void)once;
  const fs::path lf = scratch / "lf";
  std::error_code ec;
  fs::remove_all(lf, ec);
  fs::create_directories(lf, ec);
  Bytes in{data, size};
  // The views/ folder itself: a folder, or a link to one (inside or outside), or a special file.
  const uint8_t folder_kind = in.next() % 6;
  fs::path views = lf / "views";
  if (folder_kind == 1) {
    fs::create_directories(lf / "real_views", ec);
    fs::create_directory_symlink("real_views", views, ec);
    views = lf / "real_views";
  } else if (folder_kind == 2) {
    fs::create_directory_symlink("views", views, ec);  // loops
  } else if (folder_kind == 3) {
    mkfifo(views.c_str(), 0600);
  } else {
    fs::create_directories(views, ec);
  }
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c)
      MakeEntry(in, views / ("r0" + std::to_string(r) + "_c0" + std::to_string(c) + ".exr"), good, outside);
  // Extra entries named from the bytes: r<digits>_c<digits>.exr, numbers of any length.
  for (int extra = in.next() % 4; extra > 0; --extra) {
    std::string name = "r";
    for (int k = in.next() % 40; k >= 0; --k) name += char('0' + in.next() % 10);
    name += "_c0" + std::to_string(in.next() % 3) + ".exr";
    MakeEntry(in, views / name, good, outside);
  }
  // The manifest: a file, a FIFO, a loop, a folder, or a link out of the folder.
  switch (in.next() % 8) {
    case 0:
      mkfifo((lf / "lightfield.json").c_str(), 0600);
      break;
    case 1:
      fs::create_symlink("lightfield.json", lf / "lightfield.json", ec);
      break;
    case 2:
      fs::create_directory(lf / "lightfield.json", ec);
      break;
    case 3: {
      layerlab::fuzz::WriteBytes(scratch / "outside.json", reinterpret_cast<const uint8_t*>(kManifest),
                                 std::strlen(kManifest));
      fs::create_symlink(scratch / "outside.json", lf / "lightfield.json", ec);
      break;
    }
    default:
      layerlab::fuzz::WriteBytes(lf / "lightfield.json", reinterpret_cast<const uint8_t*>(kManifest),
                                 std::strlen(kManifest));
  }
  try {
    (void)layerlab::ReadLightField(lf.string(), {.load_depth = false});
  } catch (const layerlab::Error&) {
  }
  return 0;
}

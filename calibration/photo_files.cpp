#include "layerlab/calibration/photo_files.h"

#include <array>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "layerlab/framework/error.h"
#include "layerlab/framework/file_kind.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

bool Present(const fs::path& path) {
  std::error_code ec;
  return fs::symlink_status(path, ec).type() != fs::file_type::not_found;  // a dangling link is there, and named
}

}  // namespace

std::optional<PhotoFormat> PhotoFormatFromString(const std::string& name) {
  if (name == "auto") return PhotoFormat::kAuto;
  if (name == "exr") return PhotoFormat::kExr;
  if (name == "png") return PhotoFormat::kPng;
  return std::nullopt;
}

ImageFileKind ImageFileKindOf(const std::string& path) {
  RequireRegularFile(path, "photograph");  // a FIFO would block the open below
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path + ": cannot open the photograph");
  std::array<unsigned char, 8> bytes{};
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  static constexpr unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  static constexpr unsigned char kExr[4] = {0x76, 0x2f, 0x31, 0x01};
  if (in.gcount() == 8 && std::memcmp(bytes.data(), kPng, 8) == 0) return ImageFileKind::kPng;
  if (in.gcount() >= 4 && std::memcmp(bytes.data(), kExr, 4) == 0) return ImageFileKind::kExr;
  return ImageFileKind::kOther;
}

std::string ImageExtension(const std::string& name) {
  std::string tail = fs::path(name).extension().string();
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == ".exr" || tail == ".png" ? tail : "";
}

PhotoFile LocatePhoto(const std::string& folder, const std::string& name, PhotoFormat format) {
  const fs::path planned = fs::path(folder) / name;
  auto with_extension = [&](const std::string& extension) {
    fs::path other = planned;
    other.replace_extension(extension);
    return PhotoFile{other.string(), other != planned};
  };
  if (format == PhotoFormat::kExr) return with_extension(".exr");
  if (format == PhotoFormat::kPng) return with_extension(".png");
  const std::string extension = ImageExtension(name);
  if (Present(planned) || extension.empty()) return {planned.string(), false};
  const PhotoFile other = with_extension(extension == ".exr" ? ".png" : ".exr");
  return Present(other.path) ? other : PhotoFile{planned.string(), false};
}

void PhotoFilesRead::Read(const std::string& planned, const PhotoFile& file) {
  const ImageFileKind kind = ImageFileKindOf(file.path);
  const std::string name = fs::path(file.path).filename().string(), extension = ImageExtension(name);
  if (file.other_name && other_names_++ == 0) other_name_example_ = name + " for " + planned;
  const bool named_right = kind == ImageFileKind::kOther || (kind == ImageFileKind::kExr && extension == ".exr") ||
                           (kind == ImageFileKind::kPng && extension == ".png");
  if (!named_right && other_contents_++ == 0)
    other_content_example_ = name + " is " + (kind == ImageFileKind::kExr ? "an EXR" : "a PNG") + " file";
}

std::vector<std::string> PhotoFilesRead::Notes(PhotoFormat format, const std::string& response) const {
  std::vector<std::string> notes;
  if (other_names_ > 0)
    notes.push_back(std::to_string(other_names_) + " photograph" + (other_names_ > 1 ? "s were" : " was") +
                    " read from another file than the plan names (" +
                    (format == PhotoFormat::kAuto ? "the plan's is absent" : "--photo-format") + "; e.g. " +
                    other_name_example_ + "), with the plan's response \"" + response +
                    "\" (captures.json's \"response\" states a PNG's curve)");
  if (other_contents_ > 0)
    notes.push_back(std::to_string(other_contents_) + " photograph" + (other_contents_ > 1 ? "s are" : " is") +
                    " not the format " + (other_contents_ > 1 ? "their names say" : "its name says") + " and " +
                    (other_contents_ > 1 ? "were" : "was") + " read by content (e.g. " + other_content_example_ + ")");
  return notes;
}

}  // namespace layerlab

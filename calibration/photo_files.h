// Which file a capture's photograph is read from, and what that file holds.
//
// A lab that develops its photographs to PNG while the plan names EXR (the
// plan `calibration-patterns` writes does) should not have to rename them or
// edit the plan: `detect --photo-format png` reads `x.png` where the plan
// names `x.exr`, and the default (auto) does so by itself when `x.exr` is
// absent and `x.png` exists. A file is decoded by its own first bytes, not its
// extension, so a PNG saved as `x.exr` is read as the PNG it is.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace layerlab {

enum class PhotoFormat { kAuto, kExr, kPng };

// "auto", "exr", "png"; nullopt for anything else.
std::optional<PhotoFormat> PhotoFormatFromString(const std::string& name);

enum class ImageFileKind { kExr, kPng, kOther };

// What `path` holds by its signature (EXR 76 2f 31 01, PNG 89 "PNG" 0d 0a 1a 0a).
// Checks the file kind first (a FIFO would block the open): throws
// layerlab::Error naming the file when it is not a regular file or cannot be opened.
ImageFileKind ImageFileKindOf(const std::string& path);

// ".exr" or ".png" (lower case), or "" for any other name.
std::string ImageExtension(const std::string& name);

struct PhotoFile {
  std::string path;         // the file to read: the plan's name, or its stem with the other extension
  bool other_name = false;  // not the name the plan gives
};

// The file in `folder` that the plan's photograph `name` is read from under
// `format`: kExr / kPng the stem of `name` with that extension; kAuto `name`
// when anything is at that path, else the stem with the other of .exr and .png
// when that exists, else `name` (whose absence the reader then names).
// Nothing is opened here.
PhotoFile LocatePhoto(const std::string& folder, const std::string& name, PhotoFormat format);

// What `detect` says once about the files it read: how many photographs came
// from another file than the plan names, and how many hold another format
// than their names say (read by their content), each with an example.
class PhotoFilesRead {
 public:
  // Records the file read for the plan's photograph `planned`; reads its
  // signature (ImageFileKindOf: throws for a file that is missing or not regular).
  void Read(const std::string& planned, const PhotoFile& file);
  std::vector<std::string> Notes(PhotoFormat format, const std::string& response) const;

 private:
  size_t other_names_ = 0, other_contents_ = 0;
  std::string other_name_example_, other_content_example_;
};

}  // namespace layerlab

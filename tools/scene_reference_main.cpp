// scene_reference SOURCE_DIR (--write FILE | --check FILE): writes
// docs/scene-reference.md from the key tables, or checks that FILE is what
// they make (the ctest docs.scene_reference_current).
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/tools/scene_reference.h"

int main(int argc, char** argv) {
  const std::string mode = argc == 4 ? argv[2] : "";
  if (mode != "--write" && mode != "--check") {
    std::fprintf(stderr, "usage: scene_reference SOURCE_DIR (--write FILE | --check FILE)\n");
    return 2;
  }
  try {
    const std::string made = layerlab::SceneReferenceMarkdown(argv[1]), file = argv[3];
    if (mode == "--write") {
      layerlab::WriteFileAtomically(file, made);
      std::printf("wrote %s\n", file.c_str());
      return 0;
    }
    std::ifstream in(file, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    if (in && text.str() == made) {
      std::printf("%s is what the key tables make\n", file.c_str());
      return 0;
    }
    std::istringstream a(text.str()), b(made);
    std::string la, lb;
    int line = 1;
    while (true) {
      bool ga = static_cast<bool>(std::getline(a, la)), gb = static_cast<bool>(std::getline(b, lb));
      if (!ga && !gb) break;
      if (!ga || !gb || la != lb) {
        std::fprintf(stderr, "%s:%d: the file has\n  %s\nthe key tables make\n  %s\n", file.c_str(), line,
                     ga ? la.c_str() : "(end of file)", gb ? lb.c_str() : "(end of file)");
        break;
      }
      ++line;
    }
    std::fprintf(stderr,
                 "%s is not what the key tables in the sources make; regenerate it with "
                 "`cmake --build build --target scene-reference`\n",
                 file.c_str());
    return 1;
  } catch (const layerlab::Error& e) {
    std::fprintf(stderr, "scene_reference: %s\n", e.what());
    return 1;
  }
}

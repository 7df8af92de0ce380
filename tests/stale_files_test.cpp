#include "framework/stale_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "framework/atomic_file.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

TEST(StaleFiles, WhatThisProcessDidNotWriteIsRemovedAndTheRestKept) {
  const fs::path root = fs::temp_directory_path() / ("layerlab_stale_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::remove_all(root);
  fs::create_directories(root / "retina" / "old_state");
  fs::create_directories(root / "retina" / "display");
  std::ofstream(root / "retina" / "old_state" / "0.70.png") << "old";
  std::ofstream(root / "retina" / "left_over.csv") << "old";
  WriteFileAtomically((root / "retina" / "display" / "1.30.png").string(), "new");
  WriteFileAtomically((root / "retina" / "retina.csv").string(), "new");

  EXPECT_EQ(RemoveFilesNotIn((root / "retina").string(), CommittedPaths()), 2u);
  EXPECT_TRUE(fs::exists(root / "retina" / "display" / "1.30.png"));
  EXPECT_TRUE(fs::exists(root / "retina" / "retina.csv"));
  EXPECT_FALSE(fs::exists(root / "retina" / "left_over.csv"));
  EXPECT_FALSE(fs::exists(root / "retina" / "old_state"));  // emptied, so removed
  EXPECT_EQ(RemoveFilesNotIn((root / "no_such_folder").string(), CommittedPaths()), 0u);
  fs::remove_all(root);
}

TEST(StaleFiles, LinksAreRemovedAsLinksAndInputsAndLinkedFoldersStay) {
  const fs::path root = fs::temp_directory_path() / ("layerlab_stale_links_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root / "solve");
  fs::create_directories(root / "elsewhere");
  fs::create_directories(root / "target" / "lightfield");
  std::ofstream(root / "elsewhere" / "precious.txt") << "keep";
  std::ofstream(root / "target" / "lightfield" / "view_000.exr") << "input";
  fs::create_symlink(root / "no_such_file", root / "solve" / "dangling");
  fs::create_symlink(root / "elsewhere", root / "solve" / "linked_folder");
  fs::create_directory_symlink(root / "elsewhere", root / "retina");  // a step folder that is a link

  EXPECT_EQ(RemoveFilesNotIn((root / "solve").string(), {}), 2u);  // the two links, as links
  EXPECT_FALSE(fs::exists(fs::symlink_status(root / "solve" / "dangling")));
  EXPECT_TRUE(fs::exists(root / "elsewhere" / "precious.txt"));
  EXPECT_EQ(RemoveFilesNotIn((root / "retina").string(), {}), 0u);
  EXPECT_TRUE(fs::exists(root / "elsewhere" / "precious.txt"));
  EXPECT_EQ(RemoveFilesNotIn((root / "target").string(), {}, {(root / "target" / "lightfield").string()}), 0u);
  EXPECT_TRUE(fs::exists(root / "target" / "lightfield" / "view_000.exr"));
  fs::remove_all(root);
}

}  // namespace
}  // namespace layerlab

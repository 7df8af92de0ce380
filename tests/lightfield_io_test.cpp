// The light-field folder format: round trip, and every kind of bad folder
// refused with the file (and pixel, channel) named.
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>

#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

class LightFieldFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("layerlab_lf_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    LightFieldGeometry g;
    g.origin_z_m = 0.7692;
    g.window_left_m = -0.2;
    g.window_top_m = 0.1;
    g.window_width_m = 0.4;
    g.window_height_m = 0.2;
    g.cols = 8;
    g.rows = 5;
    g.views_x = 3;
    g.views_y = 2;
    lf_ = LightField(g);
    for (size_t k = 0; k < lf_.rgb.size(); ++k) lf_.rgb[k] = 0.001f * float(k % 997);
    lf_.depth.assign(g.ray_count(), 1.5f);
    lf_.scene = "test";
    WriteLightField(lf_, dir_.string());
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string ReadError() {
    try {
      ReadLightField(dir_.string());
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  }
  std::string Path(const std::string& rel) const { return (dir_ / rel).string(); }
  void EditManifest(const std::function<void(nlohmann::json&)>& edit) {
    nlohmann::json m = ReadJsonFile(Path("lightfield.json"));
    edit(m);
    std::ofstream(Path("lightfield.json")) << m.dump(2);
  }

  fs::path dir_;
  LightField lf_;
};

TEST_F(LightFieldFolder, RoundTripsExactly) {
  LightField back = ReadLightField(dir_.string());
  EXPECT_EQ(back.rgb, lf_.rgb);
  EXPECT_EQ(back.depth, lf_.depth);
  EXPECT_EQ(back.scene, "test");
  EXPECT_EQ(back.geometry.views_x, 3);
  EXPECT_DOUBLE_EQ(back.geometry.window_width_m, 0.4);
  // No temporary files are left behind.
  for (const auto& e : fs::recursive_directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

TEST_F(LightFieldFolder, ABlockOfViewRowsIsReadWholeOrRefusedWhenItRunsPastTheLastRow) {
  LightFieldReadOptions last;
  last.first_view_row = 1, last.view_rows = 1;
  const LightField row = ReadLightField(dir_.string(), last);
  ASSERT_EQ(row.rgb.size(), lf_.rgb.size() / 2);
  EXPECT_TRUE(std::equal(row.rgb.begin(), row.rgb.end(), lf_.rgb.begin() + lf_.rgb.size() / 2));
  for (const auto& [first, rows] : {std::pair{1, 2}, std::pair{2, 1}, std::pair{-1, 1}}) {
    LightFieldReadOptions o;
    o.first_view_row = first, o.view_rows = rows;
    try {
      ReadLightField(dir_.string(), o);
      ADD_FAILURE() << "view rows " << first << " to " << first + rows - 1 << " of 2 were read";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), Path("lightfield.json") + ": view rows " + std::to_string(first) + " to " +
                                           std::to_string(first + rows - 1) + " were asked for; the light field has 2");
    }
  }
}

TEST_F(LightFieldFolder, WindowOfNoWidth) {
  EditManifest([](nlohmann::json& m) { m["window"]["width"] = "0 m"; });
  EXPECT_EQ(ReadError(), Path("lightfield.json") + ": /window/width: must be in (0, 1000000] (SI units), got 0");
}

TEST_F(LightFieldFolder, MissingView) {
  fs::remove(Path("views/r01_c02.exr"));
  EXPECT_EQ(ReadError(), Path("lightfield.json") + ": view (row 1, col 2) is missing: " + Path("views/r01_c02.exr"));
}

TEST_F(LightFieldFolder, ExtraView) {
  fs::copy_file(Path("views/r01_c02.exr"), Path("views/r02_c00.exr"));
  EXPECT_EQ(ReadError(),
            Path("lightfield.json") + ": extra view file views/r02_c00.exr (the manifest declares 2 x 3 views)");
}

TEST_F(LightFieldFolder, ViewOfTheWrongSize) {
  Image small{4, 5, {"R", "G", "B"}, std::vector<float>(4 * 5 * 3, 0.5f)};
  WriteExr(Path("views/r00_c01.exr"), small);
  EXPECT_EQ(ReadError(), Path("views/r00_c01.exr") + ": is 4 x 5 pixels; the manifest declares 8 x 5");
  Image short_view{8, 4, {"R", "G", "B"}, std::vector<float>(8 * 4 * 3, 0.5f)};  // the right width, too few rows
  WriteExr(Path("views/r00_c01.exr"), short_view);
  EXPECT_EQ(ReadError(), Path("views/r00_c01.exr") + ": is 8 x 4 pixels; the manifest declares 8 x 5");
}

TEST_F(LightFieldFolder, NonFiniteAndNegativePixelsAreNamed) {
  Image image{8, 5, {"R", "G", "B"}, std::vector<float>(8 * 5 * 3, 0.5f)};
  image.pixels[(2 * 8 + 3) * 3 + 1] = NAN;
  WriteExr(Path("views/r01_c01.exr"), image);
  EXPECT_EQ(ReadError(), Path("views/r01_c01.exr") +
                             ": pixel (row 2, col 3) channel G is NaN; light must be finite and non-negative");
  image.pixels[(2 * 8 + 3) * 3 + 1] = -0.25f;
  WriteExr(Path("views/r01_c01.exr"), image);
  EXPECT_EQ(ReadError(),
            Path("views/r01_c01.exr") +
                ": pixel (row 2, col 3) channel G is negative (-0.250000); light must be finite and non-negative");
  image.pixels[(2 * 8 + 3) * 3 + 1] = INFINITY;
  WriteExr(Path("views/r01_c01.exr"), image);
  EXPECT_EQ(ReadError(), Path("views/r01_c01.exr") +
                             ": pixel (row 2, col 3) channel G is +inf; light must be finite and non-negative");
}

TEST_F(LightFieldFolder, UnknownFormatVersion) {
  EditManifest([](nlohmann::json& m) { m["format"] = "lightfield/2"; });
  EXPECT_EQ(ReadError(),
            Path("lightfield.json") +
                ": /format: unknown light-field format \"lightfield/2\"; this layerlab reads \"lightfield/1\"");
}

TEST_F(LightFieldFolder, PatternsMayNotEscapeTheFolder) {
  EditManifest([](nlohmann::json& m) { m["views_pattern"] = "../views/r{row:02}_c{col:02}.exr"; });
  EXPECT_EQ(ReadError(),
            Path("lightfield.json") +
                ": /views_pattern: \"../views/r{row:02}_c{col:02}.exr\" escapes the light-field folder ('..')");
  EditManifest([](nlohmann::json& m) { m["views_pattern"] = "/etc/r{row}_c{col}.exr"; });
  EXPECT_EQ(ReadError(), Path("lightfield.json") +
                             ": /views_pattern: \"/etc/r{row}_c{col}.exr\" must be relative to the light-field folder");
}

TEST_F(LightFieldFolder, ManifestValuesAreChecked) {
  EditManifest([](nlohmann::json& m) { m["resolution"]["cols"] = 8.5; });
  EXPECT_EQ(ReadError(), Path("lightfield.json") + ": /resolution/cols: expected an integer in [1, 16384], got 8.5");
  EditManifest([](nlohmann::json& m) {
    m["resolution"]["cols"] = 8;
    m["views"]["eyebox_widht"] = 0.006;
  });
  EXPECT_EQ(ReadError(), Path("lightfield.json") +
                             ": /views/eyebox_widht: unknown key \"eyebox_widht\"; did you mean \"eyebox_width\"?");
}

TEST_F(LightFieldFolder, TruncatedExr) {
  std::string file = Path("views/r00_c00.exr");
  fs::resize_file(file, fs::file_size(file) / 2);
  std::string error = ReadError();
  EXPECT_EQ(error.rfind(file + ": corrupt or truncated OpenEXR file: ", 0), 0u) << error;
}

TEST_F(LightFieldFolder, NotAnExr) {
  std::ofstream(Path("views/r00_c00.exr")) << "P6 8 5 255\n";
  EXPECT_EQ(ReadError(), Path("views/r00_c00.exr") + ": not an OpenEXR file");
}

// Half-float EXRs (the retinal images' default): each value within half a unit in the last of 11
// significant bits of the float, the file about half the size; a value beyond the largest half refused.
TEST(ExrPixels, HalfKeepsElevenSignificantBits) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_exr_half_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Image image{64, 32, {"R", "G", "B"}, {}};
  for (int k = 0; k < 64 * 32 * 3; ++k) image.pixels.push_back(0.001f + 1.7f * float(k % 997) / 997.f);
  WriteExr((dir / "float.exr").string(), image, ExrCompression::kNone, ExrPixels::kFloat);
  WriteExr((dir / "half.exr").string(), image, ExrCompression::kNone, ExrPixels::kHalf);
  const Image back = ReadExr((dir / "half.exr").string(), {"R", "G", "B"});
  ASSERT_EQ(back.pixels.size(), image.pixels.size());
  double worst = 0;
  for (size_t k = 0; k < image.pixels.size(); ++k)
    worst = std::max(worst, std::abs(double(back.pixels[k]) - image.pixels[k]) / image.pixels[k]);
  EXPECT_LE(worst, std::ldexp(1.0, -11));
  EXPECT_GT(worst, 0.0) << "the values were not rounded to half";
  EXPECT_LT(fs::file_size(dir / "half.exr"), 0.55 * fs::file_size(dir / "float.exr"));
  image.pixels[5] = 70000.f;
  EXPECT_THROW(WriteExr((dir / "big.exr").string(), image, ExrCompression::kNone, ExrPixels::kHalf), Error);
  EXPECT_FALSE(fs::exists(dir / "big.exr"));
  fs::remove_all(dir);
}

TEST_F(LightFieldFolder, HugeDeclaredSizeIsRefusedBeforeAllocating) {
  // Rewrite the dataWindow attribute (box2i: xmin ymin xmax ymax) to 1e9 x 1e9 pixels.
  std::string file = Path("views/r00_c00.exr");
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  size_t at = bytes.find(std::string("dataWindow\0box2i\0", 17));
  ASSERT_NE(at, std::string::npos);
  int32_t box[4] = {0, 0, 1000000000, 1000000000};
  f.seekp(std::streamoff(at + 17 + 4));
  f.write(reinterpret_cast<const char*>(box), sizeof box);
  f.close();
  std::string error = ReadError();
  EXPECT_EQ(error.rfind(file + ": ", 0), 0u) << error;
  EXPECT_NE(error.find("OpenEXR"), std::string::npos) << error;
}

// Found by fuzz/exr_fuzz (fuzz/corpus/exr/huge_attribute_size.exr and
// chlist_size_mismatch.exr): OpenEXR's C++ reader allocates a header attribute
// at its declared size before reading it, so a few hundred bytes made it
// allocate and clear gigabytes (10 to 20 s per read).
TEST_F(LightFieldFolder, AttributeSizeBeyondTheFileIsRefused) {
  std::string file = Path("views/r00_c00.exr");
  std::string bytes = std::string("\x76\x2f\x31\x01\x02\0\0\0", 8) + std::string("comments\0string\0", 16) +
                      std::string("\x00\x00\x00\x70", 4) + "a few bytes";
  std::ofstream(file, std::ios::binary) << bytes;
  EXPECT_EQ(ReadError(), file +
                             ": corrupt or truncated OpenEXR file: attribute \"comments\" declares "
                             "1879048192 bytes; the file has 11 left");
  EXPECT_THROW(ReadExrSize(file), Error);
  // The channel list declares one byte less than it holds: the C++ reader reads
  // it by content, the C core by its size, and the next attribute then read by
  // the C++ reader declares 1.6 GB.
  fs::copy_file(std::string(LAYERLAB_SOURCE_DIR) + "/fuzz/corpus/exr/chlist_size_mismatch.exr", file,
                fs::copy_options::overwrite_existing);
  std::string error = ReadError();
  EXPECT_EQ(error.rfind(file + ": corrupt or truncated OpenEXR file: attribute \"lineOrdev/1\x01\x02\" declares ", 0),
            0u)
      << error;
}

// Found by fuzz/exr_fuzz in CI (fuzz/corpus/exr/preview_size_overflow.exr): a
// preview's two 32-bit sides multiplied in 64 bits overflowed (UBSan).
TEST_F(LightFieldFolder, PreviewSidesNearTwoToThe32AreRefused) {
  std::string file = Path("views/r00_c00.exr");
  std::string bytes = std::string("\x76\x2f\x31\x01\x02\0\0\0", 8) + std::string("thumb\0preview\0", 14) +
                      std::string("\x08\0\0\0", 4) + std::string(8, '\xff') + "pixels";
  std::ofstream(file, std::ios::binary) << bytes;
  EXPECT_EQ(ReadError(), file + ": corrupt or truncated OpenEXR file: the preview image runs past the end of the file");
  fs::copy_file(std::string(LAYERLAB_SOURCE_DIR) + "/fuzz/corpus/exr/preview_size_overflow.exr", file,
                fs::copy_options::overwrite_existing);
  EXPECT_EQ(ReadError().rfind(file + ": corrupt or truncated OpenEXR file: ", 0), 0u);
}

// Issue 17: special files, links and names are refused with the path and the
// reason, before anything is opened (a FIFO view used to block the solve forever).
TEST_F(LightFieldFolder, SpecialFilesAndLinksAmongTheViewsAreRefusedWithoutBlocking) {
  const std::string view = Path("views/r00_c01.exr");
  fs::remove(view);
  ASSERT_EQ(mkfifo(view.c_str(), 0600), 0);
  EXPECT_EQ(ReadError(), view + ": the view is a FIFO, not a regular file; it is not read");
  fs::remove(view);
  fs::create_directory(view);
  EXPECT_EQ(ReadError(), view + ": the view is a folder, not a regular file; it is not read");
  fs::remove(view);
  const int s = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof address.sun_path, "%s", view.c_str());
  if (view.size() < sizeof address.sun_path && bind(s, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0) {
    EXPECT_EQ(ReadError(), view + ": the view is a socket, not a regular file; it is not read");
  }
  close(s);
  fs::remove(view);
  fs::create_symlink("/dev/zero", view);
  EXPECT_EQ(ReadError(), view + ": the view is a device, not a regular file; it is not read");
  fs::remove(view);
  fs::create_symlink("r00_c01.exr", view);  // a link to itself
  EXPECT_EQ(ReadError(), view + ": the view is a symbolic link loop (too many levels of links)");
  fs::remove(view);
  fs::create_symlink("no_such_file.exr", view);
  EXPECT_EQ(ReadError(), view + ": the view is a symbolic link to nothing (dangling)");
  fs::remove(view);
  const fs::path outside = dir_.string() + "_outside.exr";
  fs::copy_file(Path("views/r00_c00.exr"), outside, fs::copy_options::overwrite_existing);
  fs::create_symlink(outside, view);
  EXPECT_EQ(ReadError(), view + ": the view is a symbolic link to " + outside.string() + ", outside " + dir_.string() +
                             "; links out of the folder are not followed");
  fs::remove(outside);
  fs::remove(view);
  fs::create_symlink("r00_c00.exr", view);  // a link inside the folder is fine
  EXPECT_EQ(ReadError(), "");
  fs::remove(Path("lightfield.json"));
  ASSERT_EQ(mkfifo(Path("lightfield.json").c_str(), 0600), 0);
  EXPECT_EQ(ReadError(), Path("lightfield.json") + ": the manifest is a FIFO, not a regular file; it is not read");
}

TEST_F(LightFieldFolder, ViewNamesThatOverflowCollideOrExceedTheNameLimitAreRefused) {
  fs::copy_file(Path("views/r01_c02.exr"), Path("views/r99999999999999999999_c00.exr"));
  EXPECT_EQ(ReadError(),
            Path("lightfield.json") +
                ": extra view file views/r99999999999999999999_c00.exr (the manifest declares 2 x 3 views)");
  fs::remove(Path("views/r99999999999999999999_c00.exr"));
  EditManifest([](nlohmann::json& m) {
    m["views"]["rows"] = 12;
    m["views"]["cols"] = 12;
    m["views_pattern"] = "views/r{row}{col}.exr";
  });
  EXPECT_EQ(ReadError(), Path("lightfield.json") +
                             ": /views_pattern: \"views/r{row}{col}.exr\" maps views (row 1, col 10) "
                             "and (row 11, col 0) to one file, views/r110.exr");
  EditManifest([](nlohmann::json& m) {
    m["views"]["rows"] = 2;
    m["views"]["cols"] = 3;
    m["views_pattern"] = "views/" + std::string(300, 'x') + "{row}_{col}.exr";
  });
  EXPECT_EQ(ReadError(), Path("lightfield.json") + ": /views_pattern: \"" + std::string(40, 'x') +
                             "...\" is 307 bytes, beyond the file system's limit of 255 for a name");
}

TEST(DiceTarget, LoadsFromSharedData) {
  std::string folder = std::string(LAYERLAB_DATA_DIR) + "/dice";
  if (!fs::exists(folder + "/lightfield.json")) GTEST_SKIP() << "no " << folder;
  LightField lf = ReadLightField(folder);
  EXPECT_EQ(lf.geometry.ray_count(), 13u * 13 * 400 * 200);
  EXPECT_DOUBLE_EQ(lf.geometry.origin_z_m, 0.7692);
  ASSERT_EQ(lf.depth.size(), lf.geometry.ray_count());
  // Depth maps hold the dice (0.43 to 2.5 m) and the back plane at 3 m.
  auto [lo, hi] = std::minmax_element(lf.depth.begin(), lf.depth.end());
  EXPECT_GT(*lo, 0.40f);
  EXPECT_LT(*hi, 3.01f);
}

}  // namespace
}  // namespace layerlab

// The ray tiles of a partitioned solve (framework/mpi_ranks.h,
// LightFieldGeometry::ViewRows and PixelRows) and the reduction hook without MPI.
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_io.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using testing::ErrorOf;

// Every ray of a light field of `view_rows` x `pixel_rows` rows in exactly one rank's tile.
void ExpectTilesCoverEveryRowPairOnce(int view_rows, int pixel_rows, int ranks) {
  std::vector<int> owner(size_t(view_rows) * pixel_rows, -1);
  int smallest_v = view_rows, largest_v = 0, smallest_p = pixel_rows, largest_p = 0;
  for (int r = 0; r < ranks; ++r) {
    const RayTile t = RayTileOfRank(view_rows, pixel_rows, r, ranks);
    ASSERT_EQ(t.view_blocks * t.pixel_blocks, ranks);
    ASSERT_GE(t.view_rows, 1);
    ASSERT_GE(t.pixel_rows, 1);
    smallest_v = std::min(smallest_v, t.view_rows), largest_v = std::max(largest_v, t.view_rows);
    smallest_p = std::min(smallest_p, t.pixel_rows), largest_p = std::max(largest_p, t.pixel_rows);
    for (int v = t.first_view_row; v < t.first_view_row + t.view_rows; ++v)
      for (int p = t.first_pixel_row; p < t.first_pixel_row + t.pixel_rows; ++p) {
        ASSERT_EQ(owner[size_t(v) * pixel_rows + p], -1)
            << "rank " << r << " of " << ranks << " repeats " << v << ", " << p;
        owner[size_t(v) * pixel_rows + p] = r;
      }
  }
  for (int o : owner) ASSERT_NE(o, -1) << view_rows << " x " << pixel_rows << " on " << ranks;
  EXPECT_LE(largest_v - smallest_v, 1);
  EXPECT_LE(largest_p - smallest_p, 1);
}

TEST(RayTileOfRank, CoverEveryRayOnceInTilesOneRowApart) {
  for (int view_rows : {1, 2, 5, 13})
    for (int pixel_rows : {1, 3, 40, 200})
      for (int ranks = 1; ranks <= 16; ++ranks) {
        bool fits = false;  // some a x b = ranks with a <= view_rows, b <= pixel_rows
        for (int a = 1; a <= ranks; ++a) fits |= ranks % a == 0 && a <= view_rows && ranks / a <= pixel_rows;
        if (fits)
          ExpectTilesCoverEveryRowPairOnce(view_rows, pixel_rows, ranks);
        else
          EXPECT_THROW(RayTileOfRank(view_rows, pixel_rows, 0, ranks), Error) << view_rows << " x " << pixel_rows;
      }
}

TEST(RayTileOfRank, TheGridWithTheSmallestLargestTile) {
  // The paper's 13 x 200 on 8 ranks: 8 bands of 25 pixel rows (13 x 25 rows of rays each), not 2 x 4 (7 x 50).
  const RayTile t = RayTileOfRank(13, 200, 3, 8);
  EXPECT_EQ(t.view_blocks, 1);
  EXPECT_EQ(t.pixel_blocks, 8);
  EXPECT_EQ(t.first_view_row, 0);
  EXPECT_EQ(t.view_rows, 13);
  EXPECT_EQ(t.first_pixel_row, 75);
  EXPECT_EQ(t.pixel_rows, 25);
  // 5 x 3 rows on 6 ranks: 2 x 3 has tiles of at most 3 x 1, 1 x 3 cannot be (3 pixel rows), 6 x 1 neither.
  const RayTile u = RayTileOfRank(5, 3, 5, 6);
  EXPECT_EQ(u.view_blocks, 2);
  EXPECT_EQ(u.pixel_blocks, 3);
  EXPECT_EQ(u.first_view_row, 2);
  EXPECT_EQ(u.view_rows, 3);
  EXPECT_EQ(u.first_pixel_row, 2);
  EXPECT_EQ(u.pixel_rows, 1);
  // A tie (4 x 4 rows on 2 ranks: 4 x 2 or 2 x 4 rows each): bands of pixel rows.
  EXPECT_EQ(RayTileOfRank(4, 4, 1, 2).pixel_blocks, 2);
  EXPECT_EQ(RayTileOfRank(4, 4, 1, 2).first_pixel_row, 2);
  // By hand: 13 view rows on 4 ranks of 1 pixel row each are 3, 3, 3 and 4 view rows.
  EXPECT_EQ(RayTileOfRank(13, 1, 3, 4).first_view_row, 9);
  EXPECT_EQ(RayTileOfRank(13, 1, 3, 4).view_rows, 4);
  EXPECT_EQ(ErrorOf([] { RayTileOfRank(5, 40, 0, 43); }),
            "43 MPI ranks cannot share 5 view rows of 40 pixel rows: each rank holds a tile of a grid of view-row "
            "blocks by pixel-row blocks, so the rank count must be a x b with a <= 5 and b <= 40");
}

TEST(LightFieldGeometry, TileRaysAreTheWholeLightFieldsBitForBit) {
  LightFieldGeometry g;
  g.views_x = 13, g.views_y = 13, g.eyebox_width_m = 6e-3, g.eyebox_height_m = 6e-3;
  g.rows = 7, g.window_top_m = 0.31, g.window_height_m = 0.77;
  for (int first : {0, 3, 7, 12}) {
    const LightFieldGeometry tile = g.ViewRows(first, 13 - first).PixelRows(first % 7, 7 - first % 7);
    EXPECT_TRUE(tile.is_tile());
    EXPECT_EQ(tile.view_count(), size_t(13) * (13 - first));
    EXPECT_EQ(tile.whole_view_rows(), 13);
    EXPECT_EQ(tile.whole_pixel_rows(), 7);
    for (int r = 0; r < tile.views_y; ++r) {
      const double a = tile.view_y(r), b = g.view_y(first + r);
      EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "view row " << r << " of the tile from " << first;
    }
    for (int i = 0; i < tile.rows; ++i) {
      const double a = tile.pixel_y(i), b = g.pixel_y(first % 7 + i);
      EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "pixel row " << i << " of the tile from " << first % 7;
    }
    EXPECT_EQ(tile.view_x(4), g.view_x(4));
    EXPECT_FALSE(tile == g);
  }
  // By hand: row 0 of 13 over 6 mm is 3 mm - 0.5 x 6 / 13 mm; pixel row 2 of 7 over 0.77 m from 0.31 m.
  EXPECT_DOUBLE_EQ(g.ViewRows(0, 1).view_y(0), 3e-3 - 0.5 * 6e-3 / 13);
  EXPECT_DOUBLE_EQ(g.PixelRows(2, 1).pixel_y(0), 0.31 - 2.5 * 0.77 / 7);
  EXPECT_FALSE(g.is_tile());
  EXPECT_TRUE(g.PixelRows(0, 7) == g.PixelRows(0, 7));
  EXPECT_FALSE(g.PixelRows(0, 7) == g);  // the same rays, but one names itself a tile
}

TEST(NonzeroSpan, FromTheFirstToTheLastValueThatIsNotPlusZero) {
  const double v[] = {0.0, 0.0, 2.0, 0.0, -0.0, 3.0, 0.0, 0.0};
  const Span all = NonzeroSpan(v, 0, 8);
  EXPECT_EQ(all.first, 2u);
  EXPECT_EQ(all.count, 4u);                   // 2, 0, -0, 3: the zeros inside are sent
  EXPECT_EQ(NonzeroSpan(v, 3, 5).first, 1u);  // -0.0 is sent: added to a +0.0 sum it would not change it, but
  EXPECT_EQ(NonzeroSpan(v, 3, 5).count, 1u);  // to a -0.0 sum it would, so only +0.0 is left out
  EXPECT_EQ(NonzeroSpan(v, 6, 8).count, 0u);
  EXPECT_EQ(NonzeroSpan(v, 0, 2).count, 0u);
  EXPECT_EQ(NonzeroSpan(v, 5, 5).count, 0u);
  EXPECT_EQ(NonzeroSpan(v, 1, 6).first, 1u);
  EXPECT_EQ(NonzeroSpan(v, 1, 6).count, 4u);
}

TEST(SumAcrossRanks, WithoutRanksLeavesValuesAsTheyAre) {
  std::vector<double> a{1, 2}, b{3};
  double e = 4;
  SumAcrossRanks({a, b, {&e, 1}});
  EXPECT_EQ(a, (std::vector<double>{1, 2}));
  EXPECT_EQ(b, (std::vector<double>{3}));
  EXPECT_EQ(SumAcrossRanks(5.0), 5.0);
  EXPECT_EQ(MaxAcrossRanks(6.0), 6.0);
  EXPECT_TRUE(AnyRank(true));
  EXPECT_FALSE(AnyRank(false));
}

// Ranks that each hold `copies` equal shares: the sum is the value times copies.
class EqualRanks final : public RankGroup {
 public:
  int rank() const override { return 0; }
  int size() const override { return 3; }
  void Sum(double* values, size_t n) const override {
    for (size_t k = 0; k < n; ++k) values[k] = values[k] * 3 + k;  // the position shows the packing
    ++calls;
  }
  double Max(double value) const override { return value + 100; }
  bool Any(bool) const override { return true; }
  mutable int calls = 0;
};

TEST(SumAcrossRanks, PacksEveryPartIntoOneMessageInOrder) {
  EqualRanks ranks;
  const ScopedSolveRanks installed(&ranks);
  std::vector<double> a{1, 2}, b{3};
  double e = 4;
  SumAcrossRanks({a, b, {&e, 1}});
  EXPECT_EQ(ranks.calls, 1);
  EXPECT_EQ(a, (std::vector<double>{3, 7}));
  EXPECT_EQ(b, (std::vector<double>{11}));
  EXPECT_EQ(e, 15);
  std::vector<std::vector<double>> num{{1}, {2, 3}}, den{{4}};
  EXPECT_EQ(SumAcrossRanks(&num, &den, 5.0), 5.0 * 3 + 4);
  EXPECT_EQ(num, (std::vector<std::vector<double>>{{3}, {7, 11}}));
  EXPECT_EQ(den, (std::vector<std::vector<double>>{{15}}));
  EXPECT_EQ(SumAcrossRanks(nullptr, nullptr, 2.0), 6.0);
  EXPECT_EQ(MaxAcrossRanks(1.0), 101.0);
}

// A light field of cols x rows pixels and views_x x views_y views, each value its index / 1000, written to
// a fresh folder `dir`.
LightField WriteNumberedLightField(const fs::path& dir, int cols, int rows, int views_x, int views_y) {
  fs::remove_all(dir);
  LightFieldGeometry g;
  g.cols = cols, g.rows = rows, g.views_x = views_x, g.views_y = views_y;
  LightField lf(g);
  for (size_t k = 0; k < lf.rgb.size(); ++k) lf.rgb[k] = 0.001f * float(k);
  WriteLightField(lf, dir.string());
  return lf;
}

TEST(ReadLightField, ViewRowsReadsOnlyTheBlock) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_view_rows_" + std::to_string(::getpid()));
  const LightField lf = WriteNumberedLightField(dir, 4, 3, 2, 5);
  // A broken view outside the block is never read.
  std::ofstream(dir / "views" / "r00_c01.exr") << "not an EXR";
  const LightField block = ReadLightField(dir.string(), {.first_view_row = 2, .view_rows = 2});
  EXPECT_EQ(block.geometry.views_y, 2);
  EXPECT_EQ(block.geometry.first_view_row, 2);
  EXPECT_EQ(block.geometry.all_view_rows, 5);
  ASSERT_EQ(block.rgb.size(), size_t(2) * 2 * 12 * 3);
  for (size_t v = 0; v < block.geometry.view_count(); ++v)
    for (size_t k = 0; k < 36; ++k) EXPECT_EQ(block.view(v)[k], lf.view(v + 4)[k]) << "view " << v << ", value " << k;
  EXPECT_THROW(ReadLightField(dir.string()), Error);  // the whole reads the broken view
  EXPECT_EQ(ErrorOf([&] { ReadLightField(dir.string(), {.first_view_row = 4, .view_rows = 2}); }),
            (dir / "lightfield.json").string() + ": view rows 4 to 5 were asked for; the light field has 5");
  EXPECT_EQ(ErrorOf([&] { WriteLightField(block, (dir / "out").string()); }),
            (dir / "out").string() + ": internal error: a tile of a light field is not a light field to write");
  fs::remove_all(dir);
}

TEST(ReadLightField, PixelRowsReadOnlyTheTile) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_pixel_rows_" + std::to_string(::getpid()));
  const LightField lf = WriteNumberedLightField(dir, 4, 5, 2, 3);
  const LightFieldGeometry& g = lf.geometry;
  const LightField tile =
      ReadLightField(dir.string(), {.first_view_row = 1, .view_rows = 2, .first_pixel_row = 2, .pixel_rows = 2});
  EXPECT_EQ(tile.geometry, g.ViewRows(1, 2).PixelRows(2, 2));
  ASSERT_EQ(tile.rgb.size(), size_t(2) * 2 * 2 * 4 * 3);
  for (size_t v = 0; v < tile.geometry.view_count(); ++v)
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 4 * 3; ++k)
        EXPECT_EQ(tile.view(v)[i * 12 + k], lf.view(v + 2)[(i + 2) * 12 + k]) << "view " << v << ", row " << i;
  EXPECT_EQ(ErrorOf([&] { ReadLightField(dir.string(), {.first_pixel_row = 4, .pixel_rows = 2}); }),
            (dir / "lightfield.json").string() + ": pixel rows 4 to 5 were asked for; a view has 5");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace layerlab

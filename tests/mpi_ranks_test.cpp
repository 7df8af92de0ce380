// The view-row blocks of a partitioned solve (framework/mpi_ranks.h,
// LightFieldGeometry::ViewRows) and the reduction hook without MPI.
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

TEST(ViewRowsOfRank, CoverEveryRowOnceInBlocksOneApart) {
  for (int rows : {1, 2, 5, 13, 26})
    for (int ranks = 1; ranks <= rows; ++ranks) {
      int next = 0, smallest = rows, largest = 0;
      for (int r = 0; r < ranks; ++r) {
        const ViewRowBlock b = ViewRowsOfRank(rows, r, ranks);
        EXPECT_EQ(b.first, next) << rows << " rows, rank " << r << " of " << ranks;
        next = b.first + b.count;
        smallest = std::min(smallest, b.count), largest = std::max(largest, b.count);
      }
      EXPECT_EQ(next, rows);
      EXPECT_LE(largest - smallest, 1);
      EXPECT_GE(smallest, 1);
    }
  // By hand: 13 rows on 4 ranks.
  EXPECT_EQ(ViewRowsOfRank(13, 0, 4).count, 3);
  EXPECT_EQ(ViewRowsOfRank(13, 3, 4).first, 9);
  EXPECT_EQ(ViewRowsOfRank(13, 3, 4).count, 4);
}

TEST(ViewRows, BlockViewsAreTheWholeLightFieldsBitForBit) {
  LightFieldGeometry g;
  g.views_x = 13, g.views_y = 13, g.eyebox_width_m = 6e-3, g.eyebox_height_m = 6e-3;
  for (int first : {0, 3, 7, 12}) {
    const LightFieldGeometry block = g.ViewRows(first, 13 - first);
    EXPECT_TRUE(block.is_view_block());
    EXPECT_EQ(block.view_count(), size_t(13) * (13 - first));
    for (int r = 0; r < block.views_y; ++r) {
      const double a = block.view_y(r), b = g.view_y(first + r);
      EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "row " << r << " of the block from " << first;
    }
    EXPECT_EQ(block.view_x(4), g.view_x(4));
  }
  // By hand: row 0 of 13 over 6 mm is 3 mm - 0.5 x 6 / 13 mm.
  EXPECT_DOUBLE_EQ(g.ViewRows(0, 1).view_y(0), 3e-3 - 0.5 * 6e-3 / 13);
  EXPECT_FALSE(g.is_view_block());
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

TEST(ReadLightField, ViewRowsReadsOnlyTheBlock) {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_view_rows_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  LightFieldGeometry g;
  g.cols = 4, g.rows = 3, g.views_x = 2, g.views_y = 5;
  LightField lf(g);
  for (size_t k = 0; k < lf.rgb.size(); ++k) lf.rgb[k] = 0.001f * float(k);
  WriteLightField(lf, dir.string());
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
            (dir / "out").string() + ": internal error: a block of view rows is not a light field to write");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace layerlab

// The per-row kernels against plain loops in double, and their AVX2 build
// against the baseline bit for bit, on rows of every length up to 41 (both
// parities, shorter than one AVX2 step, and tails of every kind).
#include "layerlab/kernels/row_kernels.h"

#include <gtest/gtest.h>

#include "layerlab/tests/row_kernel_testing.h"

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace layerlab {
namespace {

class RowKernels : public ::testing::Test {
 protected:
  void TearDown() override { ForceRowKernels(RowKernelIsa::kAvx2); }
};

TEST_F(RowKernels, BranchLightIsTheWeightedProductOfTheLayers) {
  std::mt19937 rng(1);
  for (int layers = 1; layers <= 4; ++layers)
    for (int cols = 1; cols <= 41; ++cols) {
      std::vector<Row> in;
      for (int k = 0; k < layers; ++k) in.push_back(RandomRow(cols, rng));
      const Row start = RandomRow(cols, rng);
      const Rgb4 w{0.5f, 0.25f, 0.75f, 0.0f};
      auto run = [&] {
        const Rgb4* rows[4];
        for (int k = 0; k < layers; ++k) rows[k] = in[k].padded.data();
        std::vector<Rgb4> out = start.padded;
        out.push_back(Rgb4{kGuard, kGuard, kGuard, kGuard});
        AddBranchLightRow({rows, layers, w, cols}, out.data());
        return out;
      };
      const std::vector<Rgb4> out = run();
      for (int j = 0; j < cols; ++j)
        for (int c = 0; c < 3; ++c) {
          double p = w[c];
          for (int k = 0; k < layers; ++k) p *= in[k].padded[j][c];
          ASSERT_NEAR(out[j][c], start.padded[j][c] + p, 1e-6) << layers << " layers, ray " << j;
        }
      ASSERT_EQ(out[cols][0], kGuard);
      ExpectSameInBothBuilds([&] { return Bytes(run()); }, "branch light", cols);
    }
}

// The terms at once are the terms one by one (AddBranchLightRow in turn, the
// retinal image's order before), bit for bit, for every group remainder.
TEST_F(RowKernels, BranchLightTermsAreTheTermsAddedOneByOne) {
  std::mt19937 rng(7);
  for (int layers = 1; layers <= 4; ++layers)
    for (int terms : {1, 2, 3, 4, 5, 7, 9})
      for (int cols : {1, 2, 5, 16, 41}) {
        const int stride = 4;  // rows kept per term, as the retinal image keeps them
        std::vector<Row> in;
        for (int n = 0; n < terms * layers; ++n) in.push_back(RandomRow(cols + 2, rng));
        std::vector<const Rgb4*> rows(size_t(terms) * stride, nullptr);
        for (int q = 0; q < terms; ++q)
          for (int k = 0; k < layers; ++k) rows[q * stride + k] = in[q * layers + k].padded.data();
        std::vector<Rgb4> w;
        for (int q = 0; q < terms; ++q) w.push_back(Rgb4{0.5f + 0.01f * q, 0.25f, 0.75f - 0.02f * q, 0.0f});
        const Row start = RandomRow(cols + 2, rng);
        const int begin = cols > 2 ? 1 : 0, end = cols + (cols > 2 ? 1 : 0);  // an offset range, guards around it
        auto run = [&](bool one_by_one) {
          std::vector<Rgb4> out = start.padded;
          if (one_by_one) {
            for (int q = 0; q < terms; ++q) {
              const Rgb4* at[4];
              for (int k = 0; k < layers; ++k) at[k] = rows[q * stride + k] + begin;
              AddBranchLightRow({at, layers, w[q], end - begin}, out.data() + begin);
            }
          } else {
            AddBranchLightTermsRow({rows.data(), stride, layers, w.data(), terms}, begin, end, out.data());
          }
          return out;
        };
        const std::vector<Rgb4> at_once = run(false), one_by_one = run(true);
        ASSERT_TRUE(SameBits(at_once.data(), one_by_one.data(), at_once.size() * sizeof(Rgb4)))
            << layers << " layers, " << terms << " terms, " << cols << " rays";
        for (int j : {0, end}) {
          if (j < begin || j >= end) {
            ASSERT_TRUE(SameBits(&at_once[j], &start.padded[j], sizeof(Rgb4))) << j;
          }
        }
        ExpectSameInBothBuilds([&] { return Bytes(run(false)); }, "branch light terms", cols);
      }
}

// Several rows into the same sums are those rows one by one, bit for bit.
TEST_F(RowKernels, UpdateSumsOfSeveralRowsAreTheRowsOneByOne) {
  std::mt19937 rng(8);
  for (bool unit_q : {false, true})
    for (int rows : {1, 2, 3, 4, 5, 6, 9, 13})
      for (int cols : {1, 2, 3, 4, 17, 40, 41}) {
        std::vector<Row> r, q;
        for (int g = 0; g < rows; ++g) r.push_back(RandomRow(cols, rng)), q.push_back(RandomRow(cols, rng));
        const Row n0 = RandomRow(cols, rng), d0 = RandomRow(cols, rng);
        std::vector<const float*> rp;
        std::vector<const Rgb4*> qp;
        for (int g = 0; g < rows; ++g) rp.push_back(r[g].packed.data()), qp.push_back(q[g].padded.data());
        auto run = [&](bool one_by_one) {
          std::vector<Rgb4> num = n0.padded, den = d0.padded;
          num.push_back(Rgb4{kGuard, kGuard, kGuard, kGuard}), den.push_back(num.back());
          if (one_by_one)
            for (int g = 0; g < rows; ++g)
              UpdateSumsRow(rp[g], unit_q ? nullptr : qp[g], {num.data(), den.data()}, cols);
          else
            UpdateSumsRows(rp.data(), unit_q ? nullptr : qp.data(), rows, {num.data(), den.data()}, cols);
          std::vector<Rgb4> both = num;
          both.insert(both.end(), den.begin(), den.end());
          return both;
        };
        const std::vector<Rgb4> together = run(false), one_by_one = run(true);
        ASSERT_TRUE(SameBits(together.data(), one_by_one.data(), together.size() * sizeof(Rgb4)))
            << rows << " rows, " << cols << " rays" << (unit_q ? ", q = 1" : "");
        ASSERT_EQ(together[cols][0], kGuard);
        ExpectSameInBothBuilds([&] { return Bytes(run(false)); }, "update sums of several rows", cols);
      }
}

TEST_F(RowKernels, UpdateSumsAddTargetTimesProductAndProductSquared) {
  std::mt19937 rng(2);
  for (bool unit_q : {false, true})
    for (int cols = 1; cols <= 41; ++cols) {
      const Row r = RandomRow(cols, rng), q = RandomRow(cols, rng), n0 = RandomRow(cols, rng),
                d0 = RandomRow(cols, rng);
      auto run = [&] {
        std::vector<Rgb4> num = n0.padded, den = d0.padded;
        num.push_back(Rgb4{kGuard, kGuard, kGuard, kGuard}), den.push_back(num.back());
        UpdateSumsRow(r.packed.data(), unit_q ? nullptr : q.padded.data(), {num.data(), den.data()}, cols);
        std::vector<Rgb4> both = num;
        both.insert(both.end(), den.begin(), den.end());
        return both;
      };
      const std::vector<Rgb4> both = run();
      for (int j = 0; j < cols; ++j)
        for (int c = 0; c < 3; ++c) {
          const double qj = unit_q ? 1.0 : q.padded[j][c];
          ASSERT_NEAR(both[j][c], n0.padded[j][c] + double(r.packed[j * 3 + c]) * qj, 1e-6);
          ASSERT_NEAR(both[cols + 1 + j][c], d0.padded[j][c] + qj * qj, 1e-6);
        }
      ASSERT_EQ(both[cols][0], kGuard);
      ASSERT_EQ(both[2 * cols + 1][0], kGuard);
      // Lane 3 (padding) may differ; channels 0-2 must not.
      ExpectSameInBothBuilds(
          [&] {
            std::vector<float> rgb;
            for (const Rgb4& v : run()) rgb.insert(rgb.end(), {v[0], v[1], v[2]});
            return Bytes(rgb);
          },
          "update sums", cols);
    }
}

// A pixel-pair lattice's row (kernels/pair_lattice.h): each cell times the
// other layer's pixel its column pair names, added to (or setting) the sums.
TEST_F(RowKernels, PairSumsAddCellTimesOtherPixelAndCountTimesItsSquare) {
  std::mt19937 rng(11);
  for (bool add : {true, false})
    for (int width = 1; width <= 23; ++width) {
      const Row cells = RandomRow(width, rng, 0.0f, 9.0f), other = RandomRow(7, rng), n0 = RandomRow(width, rng),
                d0 = RandomRow(width, rng);
      std::vector<int32_t> col(width);
      for (int32_t& c : col) c = std::uniform_int_distribution<int32_t>(0, 6)(rng);
      const float rays = float(1 + width % 4);
      auto run = [&] {
        std::vector<Rgb4> num = n0.padded, den = d0.padded;
        num.push_back(Rgb4{kGuard, kGuard, kGuard, kGuard}), den.push_back(num.back());
        PairSumsRow(cells.padded.data(), other.padded.data(), rays, {col.data(), width}, add, {num.data(), den.data()});
        std::vector<Rgb4> both = num;
        both.insert(both.end(), den.begin(), den.end());
        return both;
      };
      const std::vector<Rgb4> both = run();
      for (int j = 0; j < width; ++j)
        for (int c = 0; c < 3; ++c) {
          const double q = other.padded[col[j]][c];
          ASSERT_NEAR(both[j][c], (add ? n0.padded[j][c] : 0.0) + double(cells.padded[j][c]) * q, 1e-5);
          ASSERT_NEAR(both[width + 1 + j][c], (add ? d0.padded[j][c] : 0.0) + rays * q * q, 1e-5);
        }
      ASSERT_EQ(both[width][0], kGuard);
      ASSERT_EQ(both[2 * width + 1][0], kGuard);
      ExpectSameInBothBuilds([&] { return Bytes(run()); }, "pair sums", width);
    }
}

TEST_F(RowKernels, PairSumsOfSeveralRowPairsAreTheRowPairsOneByOne) {
  std::mt19937 rng(12);
  for (int pairs : {1, 2, 3, 4, 5, 6, 9, 13})
    for (int width : {1, 2, 3, 4, 17, 40, 41}) {
      std::vector<Row> cells, other;
      std::vector<float> rays;
      for (int k = 0; k < pairs; ++k) {
        cells.push_back(RandomRow(width, rng, 0.0f, 9.0f)), other.push_back(RandomRow(7, rng));
        rays.push_back(float(1 + (k + width) % 5));
      }
      std::vector<int32_t> col(width);
      for (int32_t& c : col) c = std::uniform_int_distribution<int32_t>(0, 6)(rng);
      std::vector<const Rgb4*> cp, qp;
      for (int k = 0; k < pairs; ++k) cp.push_back(cells[k].padded.data()), qp.push_back(other[k].padded.data());
      const Row n0 = RandomRow(width, rng), d0 = RandomRow(width, rng);  // overwritten: the first pair sets the sums
      auto run = [&](bool one_by_one) {
        std::vector<Rgb4> num = n0.padded, den = d0.padded;
        num.push_back(Rgb4{kGuard, kGuard, kGuard, kGuard}), den.push_back(num.back());
        if (one_by_one)
          for (int k = 0; k < pairs; ++k)
            PairSumsRow(cp[k], qp[k], rays[k], {col.data(), width}, k > 0, {num.data(), den.data()});
        else
          PairSumsRows({cp.data(), qp.data(), rays.data(), pairs}, {col.data(), width}, {num.data(), den.data()});
        std::vector<Rgb4> both = num;
        both.insert(both.end(), den.begin(), den.end());
        return both;
      };
      const std::vector<Rgb4> together = run(false), one_by_one = run(true);
      ASSERT_TRUE(SameBits(together.data(), one_by_one.data(), together.size() * sizeof(Rgb4)))
          << pairs << " row pairs, " << width << " column pairs";
      ASSERT_EQ(together[width][0], kGuard);
      ASSERT_EQ(together[2 * width + 1][0], kGuard);
      // And the sums themselves, in double: sum_k cells_k q_k and sum_k rays_k q_k^2.
      for (int j = 0; j < width; ++j)
        for (int c = 0; c < 3; ++c) {
          double rq = 0, qq = 0;
          for (int k = 0; k < pairs; ++k) {
            const double q = other[k].padded[col[j]][c];
            rq += double(cells[k].padded[j][c]) * q, qq += rays[k] * q * q;
          }
          ASSERT_NEAR(together[j][c], rq, 1e-5 * (1 + std::abs(rq)));
          ASSERT_NEAR(together[width + 1 + j][c], qq, 1e-5 * (1 + std::abs(qq)));
        }
      ExpectSameInBothBuilds([&] { return Bytes(run(false)); }, "pair sums of several row pairs", width);
    }
}

TEST_F(RowKernels, FusedUpdateSumsAlsoGiveTheBranchError) {
  std::mt19937 rng(6);
  const Rgb4 w{0.5f, 0.25f, 0.75f, 0.0f};
  for (bool unit_q : {false, true})
    for (int cols = 1; cols <= 41; ++cols) {
      const Row r = RandomRow(cols, rng), q = RandomRow(cols, rng), own = RandomRow(cols, rng);
      const Row n0 = RandomRow(cols, rng), d0 = RandomRow(cols, rng);
      auto run = [&](double* error) {
        std::vector<Rgb4> num = n0.padded, den = d0.padded;
        *error = UpdateSumsAndErrorRow(r.packed.data(), unit_q ? nullptr : q.padded.data(), own.padded.data(), w,
                                       {num.data(), den.data()}, cols);
        std::vector<float> rgb;
        for (const std::vector<Rgb4>* v : {&num, &den})
          for (const Rgb4& x : *v) rgb.insert(rgb.end(), {x[0], x[1], x[2]});
        return rgb;
      };
      // The sums are UpdateSumsRow's, bit for bit.
      std::vector<Rgb4> num = n0.padded, den = d0.padded;
      UpdateSumsRow(r.packed.data(), unit_q ? nullptr : q.padded.data(), {num.data(), den.data()}, cols);
      double error = 0;
      const std::vector<float> fused = run(&error);
      for (int j = 0; j < cols; ++j)
        for (int c = 0; c < 3; ++c) {
          ASSERT_EQ(fused[j * 3 + c], num[j][c]);
          ASSERT_EQ(fused[(cols + j) * 3 + c], den[j][c]);
        }
      double expected = 0;
      for (int j = 0; j < cols; ++j)
        for (int c = 0; c < 3; ++c) {
          const double light = double(w[c]) * own.padded[j][c] * (unit_q ? 1.0 : q.padded[j][c]);
          const double d = r.packed[j * 3 + c] - light;
          expected += d * d;
        }
      ASSERT_NEAR(error, expected, 1e-6 * expected + 1e-12);
      ExpectSameInBothBuilds(
          [&] {
            double e = 0;
            std::vector<unsigned char> b = Bytes(run(&e));
            const unsigned char* eb = reinterpret_cast<const unsigned char*>(&e);
            b.insert(b.end(), eb, eb + sizeof e);
            return b;
          },
          "fused update sums and error", cols);
    }
}

TEST_F(RowKernels, JointSumsUseEachLayersProductOfTheOthers) {
  std::mt19937 rng(7);
  const Rgb4 w{0.5f, 0.25f, 0.75f, 0.0f};
  for (int layers = 1; layers <= 4; ++layers)
    for (bool exact_last : {true, false})
      for (int cols = 1; cols <= 41; ++cols) {
        std::vector<Row> in;
        for (int k = 0; k < layers; ++k) in.push_back(RandomRow(cols, rng));
        const Row l = RandomRow(cols, rng), light = RandomRow(cols, rng), start = RandomRow(cols, rng);
        auto run = [&] {
          std::vector<std::vector<Rgb4>> num(layers, start.padded), den(layers, start.padded);
          const Rgb4* rows[4];
          Rgb4 *n[4], *d[4];
          for (int k = 0; k < layers; ++k) rows[k] = in[k].padded.data(), n[k] = num[k].data(), d[k] = den[k].data();
          JointSumsRow({rows, layers, w, cols}, {l.packed.data(), exact_last}, light.padded.data(), {n, d});
          std::vector<float> rgb;  // res then den, layer by layer, channels 0-2
          for (const auto* sums : {&num, &den})
            for (const std::vector<Rgb4>& layer : *sums)
              for (const Rgb4& v : layer) rgb.insert(rgb.end(), {v[0], v[1], v[2]});
          return rgb;
        };
        const std::vector<float> got = run();
        const size_t per_layer = size_t(cols) * 3;
        for (int a = 0; a < layers; ++a)
          for (int j = 0; j < cols; ++j)
            for (int c = 0; c < 3; ++c) {
              double q = w[c];
              for (int k = 0; k < layers; ++k)
                if (k != a) q *= in[k].padded[j][c];
              const size_t at = a * per_layer + j * 3 + c;
              ASSERT_NEAR(got[at], start.padded[j][c] + (light.padded[j][c] - l.packed[j * 3 + c]) * q, 1e-6);
              ASSERT_NEAR(got[layers * per_layer + at], start.padded[j][c] + light.padded[j][c] * q, 1e-6);
            }
        ExpectSameInBothBuilds([&] { return Bytes(run()); }, "joint sums", cols);
      }
}

TEST_F(RowKernels, SquaredErrorIsTheDoubleSumOverChannels) {
  std::mt19937 rng(3);
  for (bool exact_last : {true, false})
    for (int cols = 1; cols <= 41; ++cols) {
      const Row t = RandomRow(cols, rng), l = RandomRow(cols, rng);
      double expected = 0;
      for (int j = 0; j < cols; ++j)
        for (int c = 0; c < 3; ++c) {
          const double d = double(t.packed[j * 3 + c]) - l.padded[j][c];
          expected += d * d;
        }
      const double got = SquaredErrorRow(t.packed.data(), l.padded.data(), cols, exact_last);
      ASSERT_NEAR(got, expected, 1e-12 * cols);
      ExpectSameInBothBuilds(
          [&] {
            const double e = SquaredErrorRow(t.packed.data(), l.padded.data(), cols, exact_last);
            return Bytes(std::vector<double>{e});
          },
          "squared error", cols);
    }
}

TEST_F(RowKernels, RemainderIsTheNonNegativePartAndWritesExactlyTheRow) {
  std::mt19937 rng(4);
  for (int cols = 1; cols <= 41; ++cols) {
    Row t = RandomRow(cols, rng, -0.5f, 1.0f);
    const Row l = RandomRow(cols, rng, 0.0f, 0.5f);
    t.packed[0] = -0.0f;  // max(-0 - 0, 0) keeps std::max's answer, -0
    auto run = [&] {
      std::vector<float> out(cols * 3 + 4, kGuard);
      RemainderRow(t.packed.data(), l.padded.data(), cols, out.data());
      return out;
    };
    const std::vector<float> out = run();
    for (int j = 0; j < cols; ++j)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(out[j * 3 + c], std::max(t.packed[j * 3 + c] - l.padded[j][c], 0.0f)) << j;
    for (int k = cols * 3; k < cols * 3 + 4; ++k) ASSERT_EQ(out[k], kGuard);
    ExpectSameInBothBuilds([&] { return Bytes(run()); }, "remainder", cols);
  }
}

TEST_F(RowKernels, PackDropsThePaddingAndWritesExactlyTheRow) {
  std::mt19937 rng(5);
  for (int cols = 1; cols <= 41; ++cols) {
    const Row in = RandomRow(cols, rng);
    auto run = [&] {
      std::vector<float> out(cols * 3 + 4, kGuard);
      PackRow(in.padded.data(), cols, out.data());
      return out;
    };
    const std::vector<float> out = run();
    for (int j = 0; j < cols; ++j)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(out[j * 3 + c], in.padded[j][c]);
    for (int k = cols * 3; k < cols * 3 + 4; ++k) ASSERT_EQ(out[k], kGuard);
    ExpectSameInBothBuilds([&] { return Bytes(run()); }, "pack", cols);
  }
}

TEST_F(RowKernels, ForcingABuildTheCpuLacksIsRefused) {
  EXPECT_TRUE(ForceRowKernels(RowKernelIsa::kBaseline));
  EXPECT_EQ(ActiveRowKernels(), RowKernelIsa::kBaseline);
  EXPECT_EQ(ForceRowKernels(RowKernelIsa::kAvx2), CpuHasAvx2());
  EXPECT_EQ(ActiveRowKernels(), CpuHasAvx2() ? RowKernelIsa::kAvx2 : RowKernelIsa::kBaseline);
}

}  // namespace
}  // namespace layerlab

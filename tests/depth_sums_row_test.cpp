// DepthSumsRow against the kernels whose operations it fuses (the display's
// light by AddBranchLightRow, the sums by JointSumsRow, the error by
// SquaredErrorRow, bit for bit), against the formulas in double, and its AVX2
// build against the baseline.
#include "layerlab/kernels/depth_sums_row.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "layerlab/tests/row_kernel_testing.h"

namespace layerlab {
namespace {

class DepthSums : public ::testing::Test {
 protected:
  void TearDown() override { ForceRowKernels(RowKernelIsa::kAvx2); }
};

struct Case {
  int layers, branches, cols;
  bool exact_last;
  std::vector<Row> in;  // [branch * layers + k]
  std::vector<int> a;   // [branch]; empty: every member's sums
  std::vector<Rgb4> w;  // [branch]
  Row l, start;
};

Case RandomCase(int layers, int branches, int cols, bool exact_last, std::mt19937& rng, bool every_member = false) {
  Case c{layers, branches, cols, exact_last, {}, {}, {}, RandomRow(cols, rng), RandomRow(cols, rng)};
  std::uniform_real_distribution<float> u(0.1f, 1.0f);
  for (int b = 0; b < branches; ++b) {
    for (int k = 0; k < layers; ++k) c.in.push_back(RandomRow(cols, rng));
    if (!every_member) c.a.push_back(static_cast<int>(rng() % layers));
    c.w.push_back(Rgb4{u(rng), u(rng), u(rng), 0.0f});
  }
  return c;
}

// The summed members, in the order of the sums: (branch, member).
std::vector<std::pair<int, int>> SummedMembers(const Case& c) {
  std::vector<std::pair<int, int>> out;
  for (int b = 0; b < c.branches; ++b)
    if (c.a.empty())
      for (int k = 0; k < c.layers; ++k) out.emplace_back(b, k);
    else
      out.emplace_back(b, c.a[b]);
  return out;
}

struct Result {
  std::vector<float> sums;  // each summed member's res and den, channels 0-2
  double error = -1;

  std::vector<unsigned char> Bytes() const {
    std::vector<unsigned char> b = layerlab::Bytes(sums);
    const unsigned char* e = reinterpret_cast<const unsigned char*>(&error);
    b.insert(b.end(), e, e + sizeof error);
    return b;
  }
};

Result RunFused(const Case& c, bool with_error = true) {
  std::vector<const Rgb4*> rows;
  for (const Row& r : c.in) rows.push_back(r.padded.data());
  const size_t summed = SummedMembers(c).size();
  std::vector<std::vector<Rgb4>> num(summed, c.start.padded), den(summed, c.start.padded);
  std::vector<Rgb4*> n, d;
  for (size_t s = 0; s < summed; ++s) n.push_back(num[s].data()), d.push_back(den[s].data());
  double error = -1;
  DepthSumsRow({rows.data(), c.layers, c.layers, c.w.data(), c.branches}, c.cols, c.a.empty() ? nullptr : c.a.data(),
               {c.l.packed.data(), c.exact_last}, with_error ? &error : nullptr, {n.data(), d.data()});
  Result out;
  for (size_t s = 0; s < summed; ++s)
    for (const auto* sums : {&num[s], &den[s]})
      for (const Rgb4& v : *sums) out.sums.insert(out.sums.end(), {v[0], v[1], v[2]});
  out.error = error;
  return out;
}

// The same from AddBranchLightRow, JointSumsRow (every member's sums, the summed ones kept) and SquaredErrorRow.
Result RunUnfused(const Case& c) {
  std::vector<Rgb4> light(c.cols, Rgb4{});
  for (int b = 0; b < c.branches; ++b) {
    const Rgb4* rows[4];
    for (int k = 0; k < c.layers; ++k) rows[k] = c.in[b * c.layers + k].padded.data();
    AddBranchLightRow({rows, c.layers, c.w[b], c.cols}, light.data());
  }
  Result out;
  for (int b = 0; b < c.branches; ++b) {
    const Rgb4* rows[4];
    std::vector<std::vector<Rgb4>> num(c.layers, c.start.padded), den(c.layers, c.start.padded);
    Rgb4 *n[4], *d[4];
    for (int k = 0; k < c.layers; ++k)
      rows[k] = c.in[b * c.layers + k].padded.data(), n[k] = num[k].data(), d[k] = den[k].data();
    JointSumsRow({rows, c.layers, c.w[b], c.cols}, {c.l.packed.data(), c.exact_last}, light.data(), {n, d});
    for (const auto& [branch, k] : SummedMembers(c))
      if (branch == b)
        for (const auto* sums : {&num[k], &den[k]})
          for (const Rgb4& v : *sums) out.sums.insert(out.sums.end(), {v[0], v[1], v[2]});
  }
  out.error = SquaredErrorRow(c.l.packed.data(), light.data(), c.cols, c.exact_last);
  return out;
}

TEST_F(DepthSums, AreTheJointSumsOfTheSummedMembersAndTheSquaredError) {
  std::mt19937 rng(11);
  for (bool every_member : {false, true})
    for (int layers = 1; layers <= 4; ++layers)
      for (int branches : {0, 1, 2, 3, 4, 5})
        for (bool exact_last : {true, false})
          for (int cols = 1; cols <= 23; ++cols) {
            const Case c = RandomCase(layers, branches, cols, exact_last, rng, every_member);
            const std::vector<std::pair<int, int>> members = SummedMembers(c);
            const Result got = RunFused(c), unfused = RunUnfused(c);
            ASSERT_EQ(got.sums, unfused.sums) << layers << " layers, " << branches << " branches, " << cols << " rays";
            ASSERT_EQ(got.error, unfused.error)
                << layers << " layers, " << branches << " branches, " << cols << " rays";
            // The formulas in double.
            const size_t n = size_t(cols) * 3;
            double error = 0;
            for (int j = 0; j < cols; ++j)
              for (int ch = 0; ch < 3; ++ch) {
                double light = 0;
                for (int b = 0; b < branches; ++b) {
                  double p = c.w[b][ch];
                  for (int k = 0; k < layers; ++k) p *= c.in[b * layers + k].padded[j][ch];
                  light += p;
                }
                const double r = c.l.packed[j * 3 + ch];
                error += (r - light) * (r - light);
                for (size_t s = 0; s < members.size(); ++s) {
                  const auto [b, a] = members[s];
                  double q = c.w[b][ch];
                  for (int k = 0; k < layers; ++k)
                    if (k != a) q *= c.in[b * layers + k].padded[j][ch];
                  const double start = c.start.padded[j][ch];
                  ASSERT_NEAR(got.sums[n * 2 * s + j * 3 + ch], start + (light - r) * q, 1e-5);
                  ASSERT_NEAR(got.sums[n * (2 * s + 1) + j * 3 + ch], start + light * q, 1e-5);
                }
              }
            ASSERT_NEAR(got.error, error, 1e-5 * (1 + error));
            ExpectSameInBothBuilds([&] { return RunFused(c).Bytes(); }, "depth sums", cols);
          }
}

TEST_F(DepthSums, WithoutTheErrorTheSumsAreTheSame) {
  std::mt19937 rng(12);
  for (int branches : {2, 5})
    for (bool every_member : {false, true}) {
      const Case c = RandomCase(2, branches, 17, true, rng, every_member);
      const Result without = RunFused(c, false), with = RunFused(c);
      EXPECT_EQ(without.error, -1.0);  // not written
      EXPECT_EQ(without.sums, with.sums);
    }
}

}  // namespace
}  // namespace layerlab

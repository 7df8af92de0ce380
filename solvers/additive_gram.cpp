#include "layerlab/solvers/additive_gram.h"

#include <map>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

using Dense = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// sum over view positions and pixels of one axis of tap_a tap_b^T.
Eigen::SparseMatrix<double, Eigen::RowMajor> AxisGram(int views, int pixels, int size_a, int size_b,
                                                      const std::function<const AxisTap*(int)>& taps_a,
                                                      const std::function<const AxisTap*(int)>& taps_b) {
  std::map<std::pair<int, int>, double> sums;
  for (int v = 0; v < views; ++v) {
    const AxisTap* ta = taps_a(v);
    const AxisTap* tb = taps_b(v);
    for (int i = 0; i < pixels; ++i) {
      const int32_t ia[2] = {ta[i].i0, ta[i].i1}, ib[2] = {tb[i].i0, tb[i].i1};
      const float wa[2] = {ta[i].w0, ta[i].w1}, wb[2] = {tb[i].w0, tb[i].w1};
      for (int p = 0; p < 2; ++p)
        for (int q = 0; q < 2; ++q)
          if (ia[p] >= 0 && ib[q] >= 0) sums[{ia[p], ib[q]}] += double(wa[p]) * wb[q];
    }
  }
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(sums.size());
  for (const auto& [index, value] : sums) entries.emplace_back(index.first, index.second, value);
  Eigen::SparseMatrix<double, Eigen::RowMajor> m(size_a, size_b);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

}  // namespace

bool AdditiveGram::Applicable(const DisplayModel& model) {
  for (size_t b = 0; b < model.branch_count(); ++b)
    if (model.branch_layers(b).size() != 1) return false;
  for (size_t k = 0; k < model.layer_count(); ++k)
    if (!model.projection(k).separable()) return false;
  return true;
}

AdditiveGram::AdditiveGram(const DisplayModel& model) : model_(model) {
  if (!Applicable(model)) throw Error("AdditiveGram: every branch must be one separable layer");
  const LightFieldGeometry& g = model.geometry();
  const int layers = static_cast<int>(model.layer_count());
  weight_.resize(layers);
  for (size_t b = 0; b < model.branch_count(); ++b) weight_[model.branch_layers(b)[0]] = model.weight(b);
  for (int a = 0; a < layers; ++a)
    for (int b = 0; b < layers; ++b) {
      const LayerProjection &Pa = model.projection(a), &Pb = model.projection(b);
      // The views of one view row share their row taps: view index r * views_x.
      auto rows_of = [&](const LayerProjection& P) {
        return [&P, &g](int r) { return P.row_taps(static_cast<size_t>(r) * g.views_x); };
      };
      auto cols_of = [](const LayerProjection& P) {
        return [&P](int c) { return P.col_taps(static_cast<size_t>(c)); };
      };
      Block block{a, b, AxisGram(g.views_y, g.rows, Pa.rows(), Pb.rows(), rows_of(Pa), rows_of(Pb)),
                  AxisGram(g.views_x, g.cols, Pa.cols(), Pb.cols(), cols_of(Pa), cols_of(Pb))};
      const int* begin = block.rows.outerIndexPtr();
      for (int r = 0; r < block.rows.outerSize(); ++r)
        if (begin[r + 1] > begin[r]) {
          if (block.end_row == 0) block.first_row = r;
          block.end_row = r + 1;
        }
      blocks_.push_back(std::move(block));
    }
}

void AdditiveGram::Apply(const LayerVectors& x, LayerVectors* out) const {
  const size_t layers = model_.layer_count();
  out->resize(layers);
  for (size_t k = 0; k < layers; ++k) (*out)[k].assign(x[k].size(), 0.0);
#pragma omp parallel for schedule(dynamic) collapse(2)
  for (size_t a = 0; a < layers; ++a)
    for (int c = 0; c < 3; ++c) {
      const LayerProjection& Pa = model_.projection(a);
      Dense sum = Dense::Zero(Pa.rows(), Pa.cols());
      for (const Block& block : blocks_) {
        // Only the rows of R_ab that hold a tap (a strip's rays reach a band
        // of the layer's rows): the others' rows of rx are 0 and would add +0.
        const int lo = block.first_row, rows = block.end_row - block.first_row;
        if (block.a != static_cast<int>(a) || rows <= 0) continue;
        const LayerProjection& Pb = model_.projection(block.b);
        Eigen::Map<const Dense, 0, Eigen::Stride<Eigen::Dynamic, 3>> xb(
            x[block.b].data() + c, Pb.rows(), Pb.cols(), Eigen::Stride<Eigen::Dynamic, 3>(3 * Pb.cols(), 3));
        const double w = double(weight_[a][c]) * weight_[block.b][c];
        Dense rx = block.rows.middleRows(lo, rows) * xb;                                      // rows x cols_b
        sum.middleRows(lo, rows).noalias() += w * (block.cols * rx.transpose()).transpose();  // rx C^T
      }
      Eigen::Map<Dense, 0, Eigen::Stride<Eigen::Dynamic, 3>> oa((*out)[a].data() + c, Pa.rows(), Pa.cols(),
                                                                Eigen::Stride<Eigen::Dynamic, 3>(3 * Pa.cols(), 3));
      oa = sum;
    }
}

}  // namespace layerlab

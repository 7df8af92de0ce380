#include "layerlab/kernels/joint_pass.h"

#include <omp.h>

#include "layerlab/framework/fixed_parts.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/kernels/joint_column_pass.h"
#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/thread_merge.h"

namespace layerlab {

JointPass::JointPass(const DisplayModel& model, SolveWorkspace* workspace,
                     const std::vector<LayerDiffraction>* diffraction)
    : model_(model), workspace_(workspace), diffraction_(diffraction && !diffraction->empty() ? diffraction : nullptr) {
  if (!workspace_) {
    own_ = std::make_unique<SolveWorkspace>(model, FixedParts(), kJointPass);
    workspace_ = own_.get();
  }
  const size_t layers = model.layer_count();
  branch_of_.assign(layers, 0);
  for (size_t b = 0; b < model.branch_count(); ++b) {
    for (int k : model.branch_layers(b)) branch_of_[k] = static_cast<int>(b);
    branch_start_.push_back(static_cast<int>(members_.size()));
    for (int k : model.branch_layers(b)) members_.push_back(k);
    for (int c = 0; c < 3; ++c) weights_.push_back(model.weight(b)[c]);
  }
  branch_start_.push_back(static_cast<int>(members_.size()));
  one_tap_ = true;
  for (size_t k = 0; k < layers; ++k) one_tap_ = one_tap_ && model.projection(k).one_tap();
  column_pass_ = true;
  for (size_t b = 0; b < model.branch_count(); ++b) column_pass_ = column_pass_ && OneTapBranch(model, b);
}

double JointPass::Run(const LightField& l, const Patterns& t, const std::vector<char>* summed, bool with_objective) {
  if (!diffraction_) return RunOn(l, t, summed, with_objective);
  DiffractPatterns(*diffraction_, t, &seen_);
  const double error = RunOn(l, seen_, summed, with_objective);
  for (size_t k = 0; k < t.size(); ++k) {
    const int layer = static_cast<int>(k);
    if ((summed && !(*summed)[k]) || !Diffracts(*diffraction_, layer)) continue;
    DiffractTransposed(*diffraction_, layer, t[k].rows, t[k].cols, &workspace_->joint_residual[k]);
    DiffractTransposed(*diffraction_, layer, t[k].rows, t[k].cols, &workspace_->joint_den[k]);
  }
  return error;
}

double JointPass::RunOn(const LightField& l, const Patterns& t, const std::vector<char>* summed, bool with_objective) {
  const size_t layers = model_.layer_count();
  std::vector<std::vector<double>>&res_ = workspace_->joint_residual, &den_ = workspace_->joint_den;
  for (size_t k = 0; k < layers; ++k)
    res_[k].resize(t[k].rgb.size()), den_[k].resize(t[k].rgb.size());  // written whole
  if (column_pass_) {
    const double error = JointColumnPass(model_, l, t, {&res_, &den_}, workspace_, summed, with_objective);
    if (!summed) return SumAcrossRanks(&res_, &den_, error);
    std::vector<std::span<double>> sums;  // of the layers summed: every rank's rays
    for (size_t k = 0; k < layers; ++k)
      if ((*summed)[k]) sums.emplace_back(res_[k]), sums.emplace_back(den_[k]);
    return SumAcrossRanks(std::move(sums), error);
  }
  // Views cut into the workspace's fixed parts (a static schedule's shares),
  // each part's sums kept apart, each view's error too (summed in view
  // order), the parts merged in part order: the same bits on any team of at
  // most that many threads (framework/fixed_parts.h).
  std::vector<double> view_error(model_.geometry().view_count());
  const int parts = workspace_->threads();
  std::vector<std::vector<const float*>> nums(layers, std::vector<const float*>(parts)),
      dens(layers, std::vector<const float*>(parts));  // [layer][part]
#pragma omp parallel
  {
    ForEachPartOfThread(parts, [&](int p) {
      ThreadWorkspace& sums = workspace_->thread(p);
      for (size_t k = 0; k < layers; ++k) {
        sums.num[k].assign(t[k].rgb.size(), 0.0f);
        sums.den[k].assign(t[k].rgb.size(), 0.0f);
        nums[k][p] = sums.num[k].data(), dens[k][p] = sums.den[k].data();
      }
      const ItemRange views = StaticShare(view_error.size(), p, parts);
      for (size_t v = views.begin; v < views.end; ++v) {
        double objective = 0;
        if (one_tap_)
          ViewOneTap(l.view(v), t, v, &sums, &objective);
        else
          ViewGeneral(l.view(v), t, v, &sums, &objective);
        view_error[v] = objective;
      }
    });
#pragma omp barrier
    const int threads = omp_get_num_threads(), me = omp_get_thread_num();
    for (size_t k = 0; k < layers; ++k) {
      MergeInThreadOrder(nums[k], res_[k].size() / 3, 3, me, threads, res_[k].data());
      MergeInThreadOrder(dens[k], den_[k].size() / 3, 3, me, threads, den_[k].data());
    }
  }
  double objective = 0;
  for (double e : view_error) objective += e;
  return SumAcrossRanks(&res_, &den_, objective);
}

// Nearest sampling, no rotation: row by row, nothing of view size stored.
void JointPass::ViewOneTap(const float* target, const Patterns& t, size_t view, ThreadWorkspace* sums,
                           double* error) const {
  const LightFieldGeometry& g = model_.geometry();
  const int layers = static_cast<int>(model_.layer_count()), branches = static_cast<int>(model_.branch_count());
  // A few values per layer, per view (this path is for branches of more layers than the column pass takes).
  std::vector<const AxisTap*> cols(layers);
  std::vector<int32_t> row_offset(layers);          // pattern offset of the layer row a ray row reads, -1: none
  std::vector<float> s(layers * 3), q(layers * 3);  // per layer and channel: its sample, the rest of its branch
  std::vector<float*> res(layers), den(layers);
  for (int k = 0; k < layers; ++k) {
    cols[k] = model_.projection(k).col_taps(view);
    res[k] = sums->num[k].data(), den[k] = sums->den[k].data();
  }
  const int* members = members_.data();
  const int* start = branch_start_.data();
  const float* weights = weights_.data();
  for (int i = 0; i < g.rows; ++i) {
    for (int k = 0; k < layers; ++k) {
      const AxisTap& r = model_.projection(k).row_taps(view)[i];
      row_offset[k] = r.i0 < 0 ? -1 : r.i0 * t[k].cols * 3;
    }
    const float* l = target + static_cast<size_t>(i) * g.cols * 3;
    double row_error = 0;
    for (int j = 0; j < g.cols; ++j, l += 3) {
      for (int k = 0; k < layers; ++k) {
        const int32_t c = cols[k][j].i0;
        if (row_offset[k] < 0 || c < 0) {
          s[k * 3] = s[k * 3 + 1] = s[k * 3 + 2] = 0.0f;
          continue;
        }
        const float* p = t[k].rgb.data() + row_offset[k] + c * 3;
        s[k * 3] = p[0], s[k * 3 + 1] = p[1], s[k * 3 + 2] = p[2];
      }
      float synthesized[3] = {0, 0, 0};
      for (int b = 0; b < branches; ++b)
        for (int ch = 0; ch < 3; ++ch) {
          // q of each member: the branch weight times the other members' samples.
          float product = weights[b * 3 + ch];
          for (int m = start[b]; m < start[b + 1]; ++m) {
            q[members[m] * 3 + ch] = product;
            product *= s[members[m] * 3 + ch];
          }
          synthesized[ch] += product;
          float suffix = 1.0f;
          for (int m = start[b + 1] - 1; m >= start[b]; --m) {
            q[members[m] * 3 + ch] *= suffix;
            suffix *= s[members[m] * 3 + ch];
          }
        }
      float residual[3];
      for (int ch = 0; ch < 3; ++ch) {
        const double e = double(l[ch]) - synthesized[ch];
        row_error += e * e;
        residual[ch] = synthesized[ch] - l[ch];
      }
      for (int a = 0; a < layers; ++a) {
        const int32_t c = cols[a][j].i0;
        if (row_offset[a] < 0 || c < 0) continue;
        const size_t pixel = static_cast<size_t>(row_offset[a]) + c * 3;
        float* re = res[a] + pixel;
        float* de = den[a] + pixel;
        for (int ch = 0; ch < 3; ++ch) {
          re[ch] += residual[ch] * q[a * 3 + ch];
          de[ch] += synthesized[ch] * q[a * 3 + ch];
        }
      }
    }
    *error += row_error;
  }
}

// Any sampling: samples per layer into view buffers, then each layer's taps.
void JointPass::ViewGeneral(const float* target, const Patterns& t, size_t view, ThreadWorkspace* sums,
                            double* error) const {
  const size_t n = model_.geometry().pixels_per_view() * 3;
  const size_t layers = model_.layer_count();
  std::vector<float>&samples = sums->samples, &synthesized = sums->synthesized;
  std::vector<float>&residual_terms = sums->residual_terms, &denominator_terms = sums->denominator_terms;
  samples.resize(layers * n), synthesized.assign(n, 0.0f), residual_terms.resize(n), denominator_terms.resize(n);
  for (size_t k = 0; k < layers; ++k) model_.projection(k).Gather(view, t[k].rgb.data(), &samples[k * n]);
  for (size_t b = 0; b < model_.branch_count(); ++b)
    for (size_t i = 0; i < n; ++i) {
      float p = model_.weight(b)[i % 3];
      for (int k : model_.branch_layers(b)) p *= samples[k * n + i];
      synthesized[i] += p;
    }
  for (size_t i = 0; i < n; ++i) {
    const double e = double(target[i]) - synthesized[i];
    *error += e * e;
  }
  for (size_t a = 0; a < layers; ++a) {
    const int b = branch_of_[a];
    for (size_t i = 0; i < n; ++i) {
      float q = model_.weight(b)[i % 3];
      for (int k : model_.branch_layers(b))
        if (k != static_cast<int>(a)) q *= samples[k * n + i];
      residual_terms[i] = (synthesized[i] - target[i]) * q;
      denominator_terms[i] = synthesized[i] * q;
    }
    model_.projection(a).ForEachChannelTap(view, [&](size_t ray, int ch, int32_t pixel, float weight) {
      sums->num[a][static_cast<size_t>(pixel) * 3 + ch] += weight * residual_terms[ray * 3 + ch];
      sums->den[a][static_cast<size_t>(pixel) * 3 + ch] += weight * denominator_terms[ray * 3 + ch];
    });
  }
}

}  // namespace layerlab

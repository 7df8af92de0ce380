// joint: every layer of every branch updated at once, from one pass over the
// rays per iteration (beyond the paper; compare it with `hybrid` on the
// error-against-time plot of `layerlab compare`).
//
// For the whole objective ||l - l~||^2, l~ = sum_b w_b prod_{k in b} P_k t_k,
// the gradient for layer a of branch b is 2 P_a^T((l~ - l) o Q_a) with
// Q_a = w_b prod_{k in b, k != a} P_k t_k. Splitting it into its positive and
// negative parts gives the multiplicative step (Lee-Seung, as tensor displays
// update their time-multiplexed frames)
//   t_a <- clamp(t_a * (P_a^T(l o Q_a) / P_a^T(l~ o Q_a))^alpha, floor, 1).
// The pass that sums those terms also yields ||l - l~||^2 of the iterate it
// reads, so an iteration costs one pass where the hybrid's costs
// 2 sets x 3 sub-iterations x 2 layers + 2 passes for the other sets' light.
//
// All layers of a branch moving at once multiply their ratios: a plain step
// uses alpha = 1 / (layers in the longest branch), which moves a uniformly
// wrong product exactly to the target. alpha over-relaxes that step: it grows
// by `kGrowth` after every iteration that lowered the objective, up to
// `kMaxRelaxation` times the plain one; an iterate that raised it is
// rejected: the previous iterate takes a plain step instead, from the ratios
// kept from its own pass, and alpha starts over.
#include <algorithm>
#include <cmath>
#include <vector>

#include "solvers/joint_column_pass.h"
#include "solvers/solve_loop.h"
#include "systems/one_tap_view.h"

namespace layerlab {
namespace {

constexpr double kGrowth = 1.3;
constexpr double kMaxRelaxation = 8.0;

// What one pass sums, per thread: per layer numerator and denominator, and the objective.
struct PassSums {
  std::vector<std::vector<float>> num, den;
  double objective = 0;
};

class JointPass {
 public:
  explicit JointPass(const DisplayModel& model) : model_(model) {
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
    num_.resize(layers), den_.resize(layers);
    column_pass_ = true;
    for (size_t b = 0; b < model.branch_count(); ++b) column_pass_ = column_pass_ && OneTapBranch(model, b);
  }

  // ratio[k][pixel * 3 + c] = numerator / denominator (or 1 where the
  // denominator is below epsilon); returns ||l - l~||^2 of `t`.
  double Run(const LightField& l, const Patterns& t, double epsilon, std::vector<std::vector<double>>* ratio) const {
    const size_t layers = model_.layer_count();
    std::vector<std::vector<double>>& num = num_;
    std::vector<std::vector<double>>& den = den_;
    for (size_t k = 0; k < layers; ++k) {
      num[k].assign(t[k].rgb.size(), 0.0);
      den[k].assign(t[k].rgb.size(), 0.0);
    }
    if (column_pass_) {
      const double objective = JointColumnPass(model_, l, t, &num, &den);
      Ratios(epsilon, ratio);
      return objective;
    }
    double objective = 0;
#pragma omp parallel reduction(+ : objective)
    {
      thread_local PassSums sums;
      sums.num.resize(layers), sums.den.resize(layers);
      for (size_t k = 0; k < layers; ++k) {
        sums.num[k].assign(t[k].rgb.size(), 0.0f);
        sums.den[k].assign(t[k].rgb.size(), 0.0f);
      }
      sums.objective = 0;
#pragma omp for schedule(dynamic)
      for (size_t v = 0; v < model_.geometry().view_count(); ++v) {
        if (one_tap_)
          ViewOneTap(l.view(v), t, v, &sums);
        else
          ViewGeneral(l.view(v), t, v, &sums);
      }
      objective += sums.objective;
#pragma omp critical
      for (size_t k = 0; k < layers; ++k)
        for (size_t i = 0; i < num[k].size(); ++i) {
          num[k][i] += sums.num[k][i];
          den[k][i] += sums.den[k][i];
        }
    }
    Ratios(epsilon, ratio);
    return objective;
  }

 private:
  void Ratios(double epsilon, std::vector<std::vector<double>>* ratio) const {
    ratio->resize(num_.size());
    for (size_t k = 0; k < num_.size(); ++k) {
      (*ratio)[k].resize(num_[k].size());
#pragma omp parallel for schedule(static)
      for (size_t i = 0; i < num_[k].size(); ++i) (*ratio)[k][i] = den_[k][i] > epsilon ? num_[k][i] / den_[k][i] : 1.0;
    }
  }

  // Nearest sampling, no rotation: row by row, nothing of view size stored.
  void ViewOneTap(const float* target, const Patterns& t, size_t view, PassSums* sums) const {
    const LightFieldGeometry& g = model_.geometry();
    const int layers = static_cast<int>(model_.layer_count()), branches = static_cast<int>(model_.branch_count());
    thread_local std::vector<const AxisTap*> cols;
    thread_local std::vector<int32_t> row_offset;  // pattern offset of the layer row a ray row reads, -1: none
    thread_local std::vector<float> s, q;           // per layer and channel: its sample, the rest of its branch
    thread_local std::vector<float*> num, den;
    cols.resize(layers), row_offset.resize(layers), s.resize(layers * 3), q.resize(layers * 3);
    num.resize(layers), den.resize(layers);
    for (int k = 0; k < layers; ++k) {
      cols[k] = model_.projection(k).col_taps(view);
      num[k] = sums->num[k].data(), den[k] = sums->den[k].data();
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
        for (int ch = 0; ch < 3; ++ch) {
          const double e = double(l[ch]) - synthesized[ch];
          row_error += e * e;
        }
        for (int a = 0; a < layers; ++a) {
          const int32_t c = cols[a][j].i0;
          if (row_offset[a] < 0 || c < 0) continue;
          const size_t pixel = static_cast<size_t>(row_offset[a]) + c * 3;
          float* nu = num[a] + pixel;
          float* de = den[a] + pixel;
          for (int ch = 0; ch < 3; ++ch) {
            nu[ch] += l[ch] * q[a * 3 + ch];
            de[ch] += synthesized[ch] * q[a * 3 + ch];
          }
        }
      }
      sums->objective += row_error;
    }
  }

  // Any sampling: samples per layer into view buffers, then each layer's taps.
  void ViewGeneral(const float* target, const Patterns& t, size_t view, PassSums* sums) const {
    const size_t n = model_.geometry().pixels_per_view() * 3;
    const size_t layers = model_.layer_count();
    thread_local std::vector<float> samples, synthesized, numerator_terms, denominator_terms;
    samples.resize(layers * n), synthesized.assign(n, 0.0f), numerator_terms.resize(n), denominator_terms.resize(n);
    for (size_t k = 0; k < layers; ++k) model_.projection(k).Gather(view, t[k].rgb.data(), &samples[k * n]);
    for (size_t b = 0; b < model_.branch_count(); ++b)
      for (size_t i = 0; i < n; ++i) {
        float p = model_.weight(b)[i % 3];
        for (int k : model_.branch_layers(b)) p *= samples[k * n + i];
        synthesized[i] += p;
      }
    for (size_t i = 0; i < n; ++i) {
      const double e = double(target[i]) - synthesized[i];
      sums->objective += e * e;
    }
    for (size_t a = 0; a < layers; ++a) {
      const int b = branch_of_[a];
      for (size_t i = 0; i < n; ++i) {
        float q = model_.weight(b)[i % 3];
        for (int k : model_.branch_layers(b))
          if (k != static_cast<int>(a)) q *= samples[k * n + i];
        numerator_terms[i] = target[i] * q;
        denominator_terms[i] = synthesized[i] * q;
      }
      model_.projection(a).ForEachTap(view, [&](size_t ray, int32_t pixel, float weight) {
        for (int ch = 0; ch < 3; ++ch) {
          sums->num[a][static_cast<size_t>(pixel) * 3 + ch] += weight * numerator_terms[ray * 3 + ch];
          sums->den[a][static_cast<size_t>(pixel) * 3 + ch] += weight * denominator_terms[ray * 3 + ch];
        }
      });
    }
  }

  const DisplayModel& model_;
  std::vector<int> branch_of_;
  std::vector<int> members_, branch_start_;  // branch b's layers: members_[branch_start_[b] .. branch_start_[b + 1])
  std::vector<float> weights_;               // [branch][channel]
  bool one_tap_ = true;
  bool column_pass_ = false;  // every branch on the one-tap path: JointColumnPass
  // Pass sums merged across threads; kept between passes (fresh megabytes would be faulted in each time).
  mutable std::vector<std::vector<double>> num_, den_;
};

// Elementwise, so the same bits for any thread count; threads because a
// power per value (a million of them for the paper's prototype) costs a
// good part of a pass.
void Step(const std::vector<std::vector<double>>& ratio, double alpha, float floor, Patterns* t) {
  for (size_t k = 0; k < t->size(); ++k) {
    std::vector<float>& p = (*t)[k].rgb;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < p.size(); ++i) {
      const double r = alpha == 1.0 ? ratio[k][i] : std::pow(ratio[k][i], alpha);
      const double updated = p[i] * r;
      // NaN fails both comparisons and lands on the floor rather than passing through.
      p[i] = updated >= 1.0 ? 1.0f : updated > floor ? static_cast<float>(updated) : floor;
    }
  }
}

class JointSolver final : public Solver {
 public:
  SolverReport Solve(const DisplayModel& model, const LightField& target, const SolverOptions& options,
                     Patterns* t) const override {
    SolveLoop loop("joint", model, target, options, t);
    if (!loop.Start()) return loop.Finish();
    const LightField& l = loop.target();
    const float floor = static_cast<float>(options.floor);
    JointPass pass(model);

    std::vector<std::vector<double>> ratio, accepted_ratio;
    double accepted_objective = pass.Run(l, *t, options.epsilon, &accepted_ratio);
    Patterns accepted = *t;
    size_t longest = 1;
    for (size_t b = 0; b < model.branch_count(); ++b) longest = std::max(longest, model.branch_layers(b).size());
    const double plain_alpha = 1.0 / static_cast<double>(longest);
    double alpha = plain_alpha;
    bool plain = true;  // the step just taken was a plain one
    if (loop.resumed()) {  // continue as after the accepted iterate the checkpoint holds
      alpha = std::min(loop.ResumedState("alpha", plain_alpha) * kGrowth, kMaxRelaxation * plain_alpha);
      plain = false;
    }
    Step(accepted_ratio, alpha, floor, t);
    while (true) {
      const double objective = pass.Run(l, *t, options.epsilon, &ratio);
      if (!(objective <= accepted_objective)) {
        *t = accepted;
        if (plain) {  // even a plain step does not descend: round-off decides from here
          loop.Converge("no multiplicative step lowers the objective any more");
          break;
        }
        // Rejected: a plain step from the last accepted iterate instead.
        alpha = plain_alpha;
        Step(accepted_ratio, alpha, floor, t);
        plain = true;
        continue;
      }
      loop.SetState("alpha", alpha);
      if (!loop.EndIteration(objective)) break;
      accepted = *t;
      accepted_objective = objective;
      std::swap(accepted_ratio, ratio);
      alpha = std::min(alpha * kGrowth, kMaxRelaxation * plain_alpha);
      Step(accepted_ratio, alpha, floor, t);
      plain = false;
    }
    // *t holds the iterate the last recorded objective belongs to.
    return loop.Finish();
  }
};

}  // namespace

SolverType JointSolverType() {
  SolverOptions defaults;
  defaults.iterations = 200;
  return {"joint", "every layer of every branch at once, one pass per iteration, over-relaxed multiplicative steps",
          [] { return std::make_unique<JointSolver>(); }, defaults};
}

}  // namespace layerlab

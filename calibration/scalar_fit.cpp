#include "layerlab/calibration/scalar_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/SVD>

namespace layerlab {
namespace {

// ceres::Covariance logs its rank-deficiency verdict as an error through glog;
// here that verdict is expected, handled and reported, so the log is muted.
class QuietCeresLog {
 public:
  QuietCeresLog() : saved_(FLAGS_minloglevel) { FLAGS_minloglevel = google::GLOG_FATAL; }
  ~QuietCeresLog() { FLAGS_minloglevel = saved_; }

 private:
  int saved_;
};

// Relative singular value below which a direction of the column-normalized
// Jacobian counts as unseen; ceres::Covariance refuses at 1e-7 unnormalized.
constexpr double kUnseen = 1e-6;

ceres::Solver::Options CeresOptionsOf(const ScalarFitOptions& options) {
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.gradient_tolerance = options.gradient_tolerance;
  solver.parameter_tolerance = options.parameter_tolerance;
  solver.logging_type = ceres::SILENT;
  solver.num_threads = 1;
  return solver;
}

// The covariance of the free parameters (`blocks`, indices `free` among
// `size`), scaled by the noise's square, into result; or why there is none.
// False when ceres::Covariance refuses it: the problem is rank deficient.
bool ScaledCovariance(ceres::Problem* problem, const std::vector<const double*>& blocks, const std::vector<int>& free,
                      int size, bool unit_noise, ScalarFitResult* result) {
  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::DENSE_SVD;
  covariance_options.apply_loss_function = true;
  ceres::Covariance covariance(covariance_options);
  bool computed;
  {
    QuietCeresLog quiet;
    computed = covariance.Compute(blocks, problem);
  }
  if (!computed) return false;
  // Whitened residuals that scatter more than the noise measured apart from
  // the fit (within what the caller tolerates) widen the uncertainties as much.
  const double noise = unit_noise ? std::max(1.0, result->noise) : result->noise;
  if (!std::isfinite(noise)) {
    result->covariance_message = "no redundancy (" + std::to_string(result->residuals) + " residuals for " +
                                 std::to_string(result->free_parameters) +
                                 " parameters): the noise, and so the "
                                 "uncertainties, cannot be estimated";
    return true;
  }
  const int n = static_cast<int>(free.size());
  Eigen::MatrixXd free_covariance(n, n);  // symmetric: row- or column-major alike
  covariance.GetCovarianceMatrix(blocks, free_covariance.data());
  result->covariance = Eigen::MatrixXd::Zero(size, size);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) result->covariance(free[a], free[b]) = free_covariance(a, b) * noise * noise;
  return true;
}

// The parameter to hold of the unseen direction v (coefficients over `free`):
// of those it involves, the lowest hold rank, then the largest coefficient.
UndeterminedParameter ParameterToHold(const Eigen::VectorXd& v, const std::vector<int>& free,
                                      const std::vector<ScalarParameter>& parameters) {
  const double largest = v.cwiseAbs().maxCoeff();
  std::vector<int> involved;
  for (int k = 0; k < v.size(); ++k)
    if (std::abs(v(k)) >= 0.1 * largest) involved.push_back(k);
  int pick = involved.front();
  for (int k : involved) {
    const int rank = parameters[free[k]].hold_rank, best = parameters[free[pick]].hold_rank;
    if (rank < best || (rank == best && std::abs(v(k)) > std::abs(v(pick)))) pick = k;
  }
  UndeterminedParameter undetermined{free[pick], {}};
  for (int k : involved)
    if (k != pick) undetermined.partners.push_back(free[k]);
  return undetermined;
}

}  // namespace

ScalarFit::ScalarFit() = default;

int ScalarFit::Add(ScalarParameter parameter) {
  values_.push_back(parameter.start);
  parameters_.push_back(std::move(parameter));
  held_.push_back(false);
  used_.push_back(false);
  return size() - 1;
}

void ScalarFit::Hold(int index) {
  held_[index] = true;
  values_[index] = parameters_[index].start;
}

void ScalarFit::AddResidual(ceres::CostFunction* cost, ceres::LossFunction* loss, const std::vector<int>& parameters) {
  std::vector<double*> blocks;
  for (int i : parameters) {
    blocks.push_back(&values_[i]);
    used_[i] = true;
  }
  problem_.AddResidualBlock(cost, loss, blocks);
}

std::vector<int> ScalarFit::FreeParameters() const {
  std::vector<int> free;
  for (int i = 0; i < size(); ++i)
    if (used_[i] && !held_[i]) free.push_back(i);
  return free;
}

double ScalarFit::EstimateNoise(const ScalarFitOptions& options, int free_count, int* residual_count) {
  ceres::Problem::EvaluateOptions evaluate;
  evaluate.apply_loss_function = false;
  std::vector<double> residuals;
  problem_.Evaluate(evaluate, nullptr, &residuals, nullptr, nullptr);
  *residual_count = static_cast<int>(residuals.size());
  const int redundancy = *residual_count - free_count;
  if (redundancy <= 0 || residuals.empty()) return std::numeric_limits<double>::quiet_NaN();
  if (options.robust_noise) {
    for (double& r : residuals) r = std::abs(r);
    auto middle = residuals.begin() + residuals.size() / 2;
    std::nth_element(residuals.begin(), middle, residuals.end());
    return 1.4826 * *middle;  // the median absolute deviation of a normal distribution, in sigmas
  }
  double sum = 0;
  for (double r : residuals) sum += r * r;
  return std::sqrt(sum / redundancy);
}

std::vector<Eigen::VectorXd> ScalarFit::NullDirections(const std::vector<int>& free) {
  ceres::Problem::EvaluateOptions evaluate;
  for (int i : free) evaluate.parameter_blocks.push_back(&values_[i]);
  ceres::CRSMatrix crs;
  problem_.Evaluate(evaluate, nullptr, nullptr, nullptr, &crs);
  const int n = static_cast<int>(free.size());
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(std::max(crs.num_rows, n), n);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[row]; k < crs.rows[row + 1]; ++k) jacobian(row, crs.cols[k]) = crs.values[k];
  for (int c = 0; c < n; ++c) {
    double norm = jacobian.col(c).norm();
    if (norm > 0) jacobian.col(c) /= norm;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(jacobian, Eigen::ComputeFullV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  std::vector<Eigen::VectorXd> unseen;
  const double largest = sigma.size() ? sigma(0) : 0.0;
  for (int k = 0; k < n; ++k)
    if (!(sigma(k) > kUnseen * largest)) unseen.push_back(svd.matrixV().col(k));
  return unseen;
}

ScalarFitResult ScalarFit::Solve(const ScalarFitOptions& options) {
  ScalarFitResult result;
  for (int i = 0; i < size(); ++i) {
    if (!used_[i]) continue;
    if (parameters_[i].lower) problem_.SetParameterLowerBound(&values_[i], 0, *parameters_[i].lower);
    if (parameters_[i].upper) problem_.SetParameterUpperBound(&values_[i], 0, *parameters_[i].upper);
  }
  const ceres::Solver::Options solver = CeresOptionsOf(options);
  while (true) {
    for (int i = 0; i < size(); ++i) {
      if (!used_[i]) continue;
      if (held_[i])
        problem_.SetParameterBlockConstant(&values_[i]);
      else
        problem_.SetParameterBlockVariable(&values_[i]);
    }
    const std::vector<int> free = FreeParameters();
    result.free_parameters = static_cast<int>(free.size());
    if (free.empty()) {
      // Nothing to solve for; the residuals still give the noise.
      result.usable = true;
      result.noise = EstimateNoise(options, 0, &result.residuals);
      result.covariance = Eigen::MatrixXd::Zero(size(), size());
      return result;
    }
    ceres::Solve(solver, &problem_, &result.summary);
    result.usable = result.summary.IsSolutionUsable();
    if (!result.usable) return result;
    result.noise = EstimateNoise(options, result.free_parameters, &result.residuals);
    std::vector<const double*> blocks;
    for (int i : free) blocks.push_back(&values_[i]);
    if (ScaledCovariance(&problem_, blocks, free, size(), options.unit_noise, &result)) return result;

    // Rank deficient: hold one parameter of the first unseen direction and solve again.
    std::vector<Eigen::VectorXd> unseen = NullDirections(free);
    if (unseen.empty()) {
      result.covariance_message =
          "the covariance is numerically singular (ceres::Covariance refused it) although "
          "no parameter direction is unseen by the data; no uncertainties are given";
      return result;
    }
    result.undetermined.push_back(ParameterToHold(unseen.front(), free, parameters_));
    Hold(result.undetermined.back().index);
  }
}

}  // namespace layerlab

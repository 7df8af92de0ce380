// A Ceres least-squares fit over named scalar parameters, each its own
// parameter block, so that a parameter can be held alone.
//
// After a usable solve the covariance comes from ceres::Covariance (DENSE_SVD),
// scaled by the noise the residuals show unless they are whitened by a noise
// measured apart from the fit (ScalarFitOptions::unit_noise; Ceres gives (J^T J)^-1, which is the
// covariance only for residuals of unit variance). When the data leave some
// direction of the parameters unseen, Compute() returns false (it must never
// be followed by GetCovariance*, which aborts): the fit then finds those
// directions itself (SVD of the column-normalized Jacobian), holds one
// parameter of each at its start value, solves again, and says which, so that
// no undetermined value is ever reported as fitted.
#pragma once

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Core>

namespace layerlab {

struct ScalarParameter {
  std::string name;  // for messages
  double start = 0;  // where the solve starts, and where a held parameter stays
  // Among parameters that move together unseen, the lowest rank is held first.
  int hold_rank = 0;
  std::optional<double> lower, upper;
};

struct ScalarFitOptions {
  int max_iterations = 200;
  double function_tolerance = 1e-14;
  double gradient_tolerance = 1e-16;
  double parameter_tolerance = 1e-13;
  // The noise is estimated from the median absolute residual instead of the
  // mean square, so that the outliers a robust loss discounts do not inflate it.
  bool robust_noise = false;
  // The residuals are whitened by a noise measured apart from the fit (one
  // standard deviation is 1): the covariance is rescaled by the residuals'
  // noise only where it exceeds 1.
  bool unit_noise = false;
};

// A parameter held at its start because the data do not determine it.
struct UndeterminedParameter {
  int index = 0;
  std::vector<int> partners;  // the others it trades off against, unseen
};

struct ScalarFitResult {
  ceres::Solver::Summary summary;  // of the last solve
  bool usable = false;
  std::vector<UndeterminedParameter> undetermined;
  // Over all parameters, rows and columns of held ones zero; empty when unavailable.
  Eigen::MatrixXd covariance;
  std::string covariance_message;  // why there is none
  double noise = 0;                // per residual component, estimated from the residuals (whatever unit_noise says)
  int residuals = 0, free_parameters = 0;
};

class ScalarFit {
 public:
  ScalarFit();
  ScalarFit(const ScalarFit&) = delete;
  ScalarFit& operator=(const ScalarFit&) = delete;

  int Add(ScalarParameter parameter);
  double value(int index) const { return values_[index]; }
  const ScalarParameter& parameter(int index) const { return parameters_[index]; }
  int size() const { return static_cast<int>(parameters_.size()); }

  // Keeps a parameter at its start value.
  void Hold(int index);
  bool held(int index) const { return held_[index]; }
  // Whether some residual depends on it.
  bool used(int index) const { return used_[index]; }

  // Takes ownership of both (loss may be null).
  void AddResidual(ceres::CostFunction* cost, ceres::LossFunction* loss, const std::vector<int>& parameters);

  ScalarFitResult Solve(const ScalarFitOptions& options);

 private:
  std::vector<int> FreeParameters() const;
  // Unseen directions of the free parameters, each as coefficients over `free`.
  std::vector<Eigen::VectorXd> NullDirections(const std::vector<int>& free);
  double EstimateNoise(const ScalarFitOptions& options, int free_count, int* residual_count);

  ceres::Problem problem_;
  std::deque<double> values_;  // stable addresses: they are the parameter blocks
  std::vector<ScalarParameter> parameters_;
  std::vector<bool> held_, used_;
};

}  // namespace layerlab

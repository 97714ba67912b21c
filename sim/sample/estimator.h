// Whole-frame totals from sampled units, with 95% confidence intervals: the stratified
// expansion estimator T = sum_h N_h mean_h with variance sum_h N_h^2 (1 - n_h/N_h) s_h^2 / n_h
// (finite-population corrected), and Student's t with n - H degrees of freedom; or the ratio
// estimator X R with R = T_y / T_x when the frame's total X of an auxiliary figure is known. A
// paired difference is the same estimator over per-unit differences.
#pragma once
#include <string>
#include <vector>

namespace rtusim {

struct Estimate {
  double value = 0.0;      // the whole-frame total
  double half_width = 0.0;  // 95% CI half-width
  double ci_low() const { return value - half_width; }
  double ci_high() const { return value + half_width; }
  // Half-width relative to the estimate (0 when both are 0).
  double relative_half_width() const;
  bool valid = true;     // false: too few units, or a stratum with fewer than two
  std::string problem;   // why not valid
};

// Two-sided 95% quantile of Student's t with `df` degrees of freedom (df >= 1).
double t_quantile_95(int df);

class Estimator {
 public:
  // `stratum_units`: the population's units per stratum; `min_units`: fewer taken is not valid.
  Estimator(std::vector<double> stratum_units, int min_units);

  // `values[i]` is the figure measured on a unit of stratum `strata[i]`.
  Estimate total(const std::vector<double>& values, const std::vector<int>& strata) const;

  // The combined ratio estimator: `x_total` (known for the whole frame) x the ratio of the
  // estimated totals of `values` and `x` (x[i]: the auxiliary figure of unit i, e.g. its rays),
  // with the usual linearized variance, total()'s over the residuals values[i] - R x[i],
  // scaled by (X / X_hat)^2.
  Estimate ratio(const std::vector<double>& values, const std::vector<double>& x, double x_total,
                 const std::vector<int>& strata) const;

 private:
  std::vector<double> stratum_units_;
  int min_units_;
};

}  // namespace rtusim

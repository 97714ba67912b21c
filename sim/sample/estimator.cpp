#include "sample/estimator.h"

#include <cmath>

namespace rtusim {

double Estimate::relative_half_width() const {
  if (half_width == 0.0) return 0.0;
  return value != 0.0 ? half_width / std::abs(value) : INFINITY;
}

double t_quantile_95(int df) {
  static const double kTable[30] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306,
                                    2.262,  2.228, 2.201, 2.179, 2.160, 2.145, 2.131, 2.120,
                                    2.110,  2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
                                    2.060,  2.056, 2.052, 2.048, 2.045, 2.042};
  if (df < 1) return INFINITY;
  if (df <= 30) return kTable[df - 1];
  // Cornish-Fisher expansion around the normal quantile (error < 1e-4 beyond 30 df).
  const double z = 1.959963984540054, n = df;
  const double z3 = z * z * z, z5 = z3 * z * z;
  return z + (z3 + z) / (4 * n) + (5 * z5 + 16 * z3 + 3 * z) / (96 * n * n);
}

Estimator::Estimator(std::vector<double> stratum_units, int min_units)
    : stratum_units_(std::move(stratum_units)), min_units_(min_units) {}

Estimate Estimator::total(const std::vector<double>& values, const std::vector<int>& strata) const {
  const size_t h_count = stratum_units_.size();
  std::vector<double> n(h_count, 0.0), sum(h_count, 0.0), sum_sq(h_count, 0.0);
  for (size_t i = 0; i < values.size(); ++i) {
    n[strata[i]] += 1.0;
    sum[strata[i]] += values[i];
  }
  for (size_t i = 0; i < values.size(); ++i) {
    const int h = strata[i];
    const double d = values[i] - sum[h] / n[h];
    sum_sq[h] += d * d;
  }
  Estimate e;
  const size_t taken = values.size();
  // Every unit drawn (a census): the total is the frame's own, exactly.
  double population = 0.0;
  for (const double units : stratum_units_) population += units;
  if (taken > 0 && double(taken) == population) {
    for (const double v : values) e.value += v;
    return e;
  }
  bool strata_ok = true;
  for (size_t h = 0; h < h_count; ++h) strata_ok = strata_ok && n[h] >= 2.0;
  double variance = 0.0;
  int df = 0;
  if (strata_ok) {
    for (size_t h = 0; h < h_count; ++h) {
      const double big_n = stratum_units_[h];
      e.value += big_n * sum[h] / n[h];
      variance += big_n * big_n * (1.0 - n[h] / big_n) * (sum_sq[h] / (n[h] - 1.0)) / n[h];
    }
    df = static_cast<int>(taken - h_count);
  } else {
    // A stratum with fewer than two units has no variance of its own: the sample is taken as
    // one simple random sample of the whole population, and flagged.
    double big_n = 0.0, all_sum = 0.0;
    for (size_t h = 0; h < h_count; ++h) big_n += stratum_units_[h], all_sum += sum[h];
    const double mean = taken ? all_sum / double(taken) : 0.0;
    double ss = 0.0;
    for (double v : values) ss += (v - mean) * (v - mean);
    e.value = big_n * mean;
    if (taken >= 2)
      variance = big_n * big_n * (1.0 - double(taken) / big_n) * (ss / double(taken - 1)) /
                 double(taken);
    df = static_cast<int>(taken) - 1;
    e.valid = false;
    e.problem = "a stratum has fewer than 2 units";
  }
  e.half_width = df >= 1 ? t_quantile_95(df) * std::sqrt(std::max(0.0, variance)) : INFINITY;
  if (static_cast<int>(taken) < min_units_) {
    e.valid = false;
    e.problem = std::to_string(taken) + " units < sample.min_units = " +
                std::to_string(min_units_);
  }
  return e;
}

Estimate Estimator::ratio(const std::vector<double>& values, const std::vector<double>& x,
                          double x_total, const std::vector<int>& strata) const {
  const Estimate y_hat = total(values, strata), x_hat = total(x, strata);
  const double r = x_hat.value != 0.0 ? y_hat.value / x_hat.value : 0.0;
  std::vector<double> residuals(values.size());
  for (size_t i = 0; i < values.size(); ++i) residuals[i] = values[i] - r * x[i];
  Estimate e = total(residuals, strata);  // its value is ~0; its half-width is the ratio's
  e.value = r * x_total;
  // Scaled by X / X_hat (Cochran's v2): wider when the drawn units have fewer rays than their
  // share, which is when R is least sure; 93 -> 95 of 100 CIs hold on the built-in room.
  if (x_hat.value > 0.0) e.half_width *= x_total / x_hat.value;
  return e;
}

}  // namespace rtusim

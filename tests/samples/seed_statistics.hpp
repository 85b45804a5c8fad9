// Statistics over independent runs (seeds) for estimators whose samples are not independent: with a
// low-discrepancy sampler the spread of one sequence's samples says nothing about the error of their
// mean, but independent scramblings (seeds) are independent estimates, so their spread does.
#pragma once

#include <cmath>
#include <numeric>
#include <vector>

namespace statepack::testing {

// Two-sided tail P(|T| > t) of Student's t with nu degrees of freedom: the integral of the density
// from t to infinity, substituted x = t / s so the range is (0, 1], by Simpson's rule.
inline double student_t_tail(double t, double nu) {
  const double log_norm = std::lgamma((nu + 1) / 2) - std::lgamma(nu / 2) - 0.5 * std::log(nu * M_PI);
  auto density = [&](double x) { return std::exp(log_norm - (nu + 1) / 2 * std::log1p(x * x / nu)); };
  auto integrand = [&](double s) { return s <= 0 ? 0.0 : density(t / s) * t / (s * s); };
  const int n = 4000;
  double sum = integrand(0) + integrand(1);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4 : 2) * integrand(double(i) / n);
  return 2 * sum / (3.0 * n);
}

// The critical |t| of a Sidak-corrected two-sided test at family-wise level alpha over `tests` tests.
inline double sidak_t(double alpha, size_t tests, double nu) {
  const double per_test = 1.0 - std::pow(1.0 - alpha, 1.0 / double(tests));
  double lo = 0, hi = 1000;
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo + hi) / 2;
    (student_t_tail(mid, nu) > per_test ? lo : hi) = mid;
  }
  return lo;
}

// Mean and variance of the mean of independent estimates.
inline std::pair<double, double> mean_and_variance_of_mean(const std::vector<double>& v) {
  const double n = double(v.size());
  const double m = std::accumulate(v.begin(), v.end(), 0.0) / n;
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return {m, s / (n - 1) / n};
}

}  // namespace statepack::testing

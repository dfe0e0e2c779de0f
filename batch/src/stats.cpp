#include <stbatch/stats.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace st::batch {

double studentT975(int dof) {
  // t_{0.975, dof}, dof = 1..30 (standard tables); beyond, the Cornish-Fisher expansion around the
  // normal quantile, accurate to better than 1e-4 for dof > 30.
  static constexpr std::array<double, 30> table = {
      12.706205, 4.302653, 3.182446, 2.776445, 2.570582, 2.446912, 2.364624, 2.306004, 2.262157, 2.228139,
      2.200985,  2.178813, 2.160369, 2.144787, 2.131450, 2.119905, 2.109816, 2.100922, 2.093024, 2.085963,
      2.079614,  2.073873, 2.068658, 2.063899, 2.059539, 2.055529, 2.051831, 2.048407, 2.045230, 2.042272};
  if (dof < 1) return std::nan("");
  if (dof <= 30) return table[dof - 1];
  const double z = 1.959963984540054, n = dof;
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z;
  return z + (z3 + z) / (4 * n) + (5 * z5 + 16 * z3 + 3 * z) / (96 * n * n) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * n * n * n);
}

Summary summarize(const std::vector<double>& xs) {
  Summary s;
  s.n = static_cast<int>(xs.size());
  if (s.n == 0) return s;
  // two-pass: mean, then squared deviations (no cancellation)
  double sum = 0.0;
  for (double x : xs) sum += x;
  s.mean = sum / s.n;
  if (s.n < 2) return s;
  double ss = 0.0;
  for (double x : xs) ss += (x - s.mean) * (x - s.mean);
  s.sd = std::sqrt(ss / (s.n - 1));
  s.ci95 = studentT975(s.n - 1) * s.sd / std::sqrt(static_cast<double>(s.n));
  return s;
}

double median(std::vector<double> xs) {
  if (xs.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(xs.begin(), xs.end());
  const std::size_t n = xs.size();
  return n % 2 ? xs[n / 2] : 0.5 * (xs[n / 2 - 1] + xs[n / 2]);
}

}  // namespace st::batch

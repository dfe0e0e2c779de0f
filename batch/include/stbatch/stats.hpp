#pragma once
// Summary statistics over seeds.
#include <vector>

namespace st::batch {

struct Summary {
  int n = 0;
  double mean = 0.0;
  double sd = 0.0;         // sample standard deviation (n - 1)
  double ci95 = 0.0;       // half-width of the two-sided 95% confidence interval of the mean (Student t)
};

Summary summarize(const std::vector<double>& xs);

// The median of xs (NaN when empty).
double median(std::vector<double> xs);

// Two-sided 97.5% quantile of Student's t with `dof` degrees of freedom.
double studentT975(int dof);

}  // namespace st::batch

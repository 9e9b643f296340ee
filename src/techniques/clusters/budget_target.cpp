#include "farfield/techniques/clusters/budget_target.hpp"

#include <algorithm>
#include <cmath>

namespace farfield {

void BudgetTarget::observe(double predicted_ms, double measured_ms, double budget_ms) {
  if (!(predicted_ms > 0.0) || !(measured_ms > 0.0) || !std::isfinite(measured_ms)) return;
  if (std::max(predicted_ms, measured_ms) < 0.5 * budget_ms) return;
  ratios_[next_] = measured_ms / predicted_ms;
  next_ = (next_ + 1) % kFrames;
  count_ = std::min(count_ + 1, kFrames);
}

double BudgetTarget::target_ms(double budget_ms) const {
  if (count_ < kFewest) return 0.9 * budget_ms;
  std::array<double, kFrames> sorted = ratios_;
  const auto q = sorted.begin() + std::ptrdiff_t(std::floor(quantile_ * double(count_ - 1)));
  std::nth_element(sorted.begin(), q, sorted.begin() + std::ptrdiff_t(count_));
  return budget_ms * std::clamp(1.1 / std::max(*q, 1e-3), 0.6, 0.95);
}

}  // namespace farfield

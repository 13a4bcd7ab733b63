#pragma once
// Shared check of fitted log-normal Laguerre cells (box and disc tests).

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry/laguerre.hpp"

namespace cleave::testing {

/// Each cell within 1 % of its target volume, and the sample standard deviation of ln d
/// (d = (6 V / pi)^(1/3)) within five standard errors of sigma = sqrt(ln(1 + cv^2)).
inline void expect_lognormal_cells(const geometry::LaguerreTessellation& t, double cv) {
  const double pi = 3.14159265358979323846;
  const std::size_t n = t.cells.size();
  std::vector<double> logs;
  double mean_log = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = t.cells[i].volume().to_double();
    EXPECT_NEAR(v, t.targets[i], 0.01 * t.targets[i]) << i;
    logs.push_back(std::log(std::cbrt(6.0 * v / pi)));
    mean_log += logs.back() / static_cast<double>(n);
  }
  double var = 0.0;
  for (double l : logs) var += (l - mean_log) * (l - mean_log) / static_cast<double>(n - 1);
  const double sigma = std::sqrt(std::log(1.0 + cv * cv));
  EXPECT_NEAR(std::sqrt(var), sigma, 5.0 * sigma / std::sqrt(2.0 * static_cast<double>(n)));
}

}  // namespace cleave::testing

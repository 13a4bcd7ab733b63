/// \file
/// The standard tests' formulas and the honeycomb's elasticity (see standard_tests.hpp).

#include "validation/standard_tests.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace cleave::physics {

/// Brazilian test, sec. 2.5.4 of the dissertation.
double brazilian_tensile_strength(double load, double diameter, double thickness) {
  return 2.0 * load / (M_PI * diameter * thickness);
}

/// Four-point flexure, beam theory (the dissertation's sec. 2.5.3 with its factor 3; ASTM C1161).
double four_point_flexural_strength(double load, double outer_span, double inner_span,
                                    double width, double depth) {
  return 3.0 * load * (outer_span - inner_span) / (2.0 * width * depth * depth);
}

/// ASTM C1421, three-point SENB with S/W = 4 (Srawley's fit).
double senb_geometry_factor(double alpha) {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    throw std::invalid_argument("senb_geometry_factor: a/W must lie in (0, 1), got " +
                                std::to_string(alpha));
  }
  const double poly = 1.99 - alpha * (1.0 - alpha) * (2.15 - 3.93 * alpha + 2.7 * alpha * alpha);
  return 3.0 * std::sqrt(alpha) * poly / (2.0 * (1.0 + 2.0 * alpha) * std::pow(1.0 - alpha, 1.5));
}

double senb_stress_intensity(double load, double span, double thickness, double depth,
                             double crack) {
  return load * span / (thickness * std::pow(depth, 1.5)) * senb_geometry_factor(crack / depth);
}

double edge_notch_tension_stress_intensity(double force, double thickness, double width, double crack) {
  const double alpha = crack / width;
  if (!(alpha > 0.0 && alpha < 1.0)) {
    throw std::invalid_argument("edge_notch_tension_stress_intensity: a/W must lie in (0, 1), got " +
                                std::to_string(alpha));
  }
  const double h = 0.5 * M_PI * alpha;
  const double f = std::sqrt(std::tan(h) / h) * (0.752 + 2.02 * alpha + 0.37 * std::pow(1.0 - std::sin(h), 3)) /
                   std::cos(h);
  return force / (thickness * width) * std::sqrt(M_PI * crack) * f;
}

/// The triangular lattice of normal and shear springs (derivation in standard_tests.hpp):
/// lambda = sqrt(3)/4 (K_n - K_s), mu = sqrt(3)/4 (K_n + K_s) per unit thickness.
HoneycombElasticity honeycomb_elasticity(double kn, double ks, double thickness) {
  const double lambda = std::sqrt(3.0) / 4.0 * (kn - ks);
  const double mu = std::sqrt(3.0) / 4.0 * (kn + ks);
  HoneycombElasticity e;
  e.poisson = lambda / (lambda + 2.0 * mu);
  e.young = 4.0 * mu * (lambda + mu) / (lambda + 2.0 * mu) / thickness;
  return e;
}

BondSprings honeycomb_springs(double young, double poisson, double thickness) {
  if (!(young > 0.0)) throw std::invalid_argument("honeycomb_springs: E must be > 0");
  if (!(poisson >= 0.0 && poisson <= 1.0 / 3.0)) {
    throw std::invalid_argument(
        "honeycomb_springs: a honeycomb of normal and shear springs has 0 <= nu <= 1/3, got " +
        std::to_string(poisson));
  }
  const double ratio = (1.0 - 3.0 * poisson) / (1.0 + poisson);  // K_s / K_n
  BondSprings s;
  s.kn = young * thickness * (3.0 + ratio) / (2.0 * std::sqrt(3.0) * (1.0 + ratio));
  s.ks = ratio * s.kn;
  return s;
}

AffineFit fit_affine(const std::vector<Eigen::Vector2d>& positions,
                     const std::vector<Eigen::Vector2d>& displacements) {
  const std::size_t n = positions.size();
  if (n != displacements.size()) throw std::invalid_argument("fit_affine: sizes differ");
  Eigen::Vector2d mean = Eigen::Vector2d::Zero(), umean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    mean += positions[i];
    umean += displacements[i];
  }
  if (n < 3) throw std::invalid_argument("fit_affine: needs three points or more");
  mean /= static_cast<double>(n);
  umean /= static_cast<double>(n);
  // Normal equations about the centroid: G (sum dx dx^T) = sum du dx^T.
  Eigen::Matrix2d xx = Eigen::Matrix2d::Zero(), ux = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d dx = positions[i] - mean, du = displacements[i] - umean;
    xx += dx * dx.transpose();
    ux += du * dx.transpose();
  }
  if (!(xx.determinant() > 1e-12 * xx.trace() * xx.trace())) {
    throw std::invalid_argument("fit_affine: the points lie on one line");
  }
  AffineFit fit;
  fit.gradient = ux * xx.inverse();
  fit.translation = umean - fit.gradient * mean;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sum += (displacements[i] - fit.translation - fit.gradient * positions[i]).squaredNorm();
  }
  fit.rms_residual = std::sqrt(sum / static_cast<double>(n));
  return fit;
}

}  // namespace cleave::physics

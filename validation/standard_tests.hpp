#pragma once
/// \file
/// The formulas of the standard tests of ceramics, which turn a test's peak load into the
/// property a handbook lists, and the closed-form elasticity of a bonded honeycomb, which
/// `cleave measure` and `cleave calibrate` compare with:
/// - the Brazilian disc: sigma_t = 2P / (pi D t) (sec. 2.5.4 of the dissertation, seed 000);
/// - four-point flexure by beam theory (ASTM C1161): sigma_f = 3P (L - L_i) / (2 b d^2)
///   for a total load P, outer span L and inner span L_i. The dissertation (sec. 2.5.3)
///   prints sigma = P L_i / (w t^2) with its L_i the distance from a support to the nearer
///   loading roller, (L - L_i) / 2 here. Beam theory gives 6M / (w t^2) with the moment
///   between the loading rollers M = (P/2) L_i, three times the printed value: the print
///   drops the factor 3, and cleave uses beam theory;
/// - the single-edge notched beam in three-point flexure with support span S = 4W (ASTM
///   C1421, the stress-intensity fit of Srawley 1976), K_I = [P S / (B W^1.5)] Y(a/W);
/// - the bonded honeycomb: grains on a triangular lattice, each pair joined by a normal and
///   a shear spring (K_n = k_bn A_b and K_s = k_bs A_b, eq. 2.10 of the dissertation), is in
///   homogeneous strain an isotropic plate with Lame constants lambda = sqrt(3)/4 (K_n - K_s)
///   and mu = sqrt(3)/4 (K_n + K_s) per unit thickness (energy per grain, (1/4) sum of the six
///   springs' energies, over its cell's area sqrt(3)/2 l^2; grains do not turn in
///   homogeneous strain, the moments of the six bonds cancelling by symmetry), so in plane
///   stress nu = (K_n - K_s) / (3 K_n + K_s) and E t = 2 sqrt(3) K_n (K_n + K_s) / (3 K_n + K_s),
///   whatever the grain size.

#include <Eigen/Dense>

#include <vector>

namespace cleave::physics {

/// sigma_t = 2P / (pi D t): P the load across the diameter D, t the disc's thickness.
double brazilian_tensile_strength(double load, double diameter, double thickness);

/// sigma_f = 3P (L - L_i) / (2 b d^2): P the total load of the two loading rollers, L the
/// support span, L_i the loading span, b the width (the prisms' length), d the depth.
double four_point_flexural_strength(double load, double outer_span, double inner_span,
                                    double width, double depth);

/// Y(alpha) of ASTM C1421's three-point SENB (S/W = 4): 3 sqrt(alpha) [1.99 - alpha (1 -
/// alpha)(2.15 - 3.93 alpha + 2.7 alpha^2)] / [2 (1 + 2 alpha)(1 - alpha)^1.5].
double senb_geometry_factor(double alpha);
/// K_I = P S / (B W^1.5) Y(a / W): P the load, S the support span, B the thickness, W the
/// depth, a the notch (crack) depth. Valid for S / W = 4 and 0 < a / W < 1.
double senb_stress_intensity(double load, double span, double thickness, double depth,
                             double crack);

/// K_I of an edge crack of depth a in a strip of width W and thickness B pulled by a force N
/// along the strip's centre line (N > 0: tension), free to bend: sigma sqrt(pi a) F(a/W),
/// sigma = N / (B W), F(alpha) = sqrt(2 / (pi alpha) tan(pi alpha / 2)) [0.752 + 2.02 alpha +
/// 0.37 (1 - sin(pi alpha / 2))^3] / cos(pi alpha / 2) (Tada, Paris and Irwin, The Stress
/// Analysis of Cracks Handbook, single edge notch in tension: within 0.5 % for any a/W).
/// Valid for 0 < a / W < 1.
double edge_notch_tension_stress_intensity(double force, double thickness, double width, double crack);

/// In-plane elasticity of a bonded honeycomb of thickness t (the prisms' length).
struct HoneycombElasticity {
  double young = 0.0;    ///< E, Pa
  double poisson = 0.0;  ///< nu (plane stress, in the plane of the honeycomb)
};
HoneycombElasticity honeycomb_elasticity(double kn, double ks, double thickness);
/// The springs that give E and nu: K_s / K_n = (1 - 3 nu) / (1 + nu), so nu <= 1/3.
/// Throws std::invalid_argument for nu outside [0, 1/3] or E <= 0.
struct BondSprings {
  double kn = 0.0;  ///< N/m
  double ks = 0.0;  ///< N/m
};
BondSprings honeycomb_springs(double young, double poisson, double thickness);

/// The affine displacement field u = c + G x that fits the points' displacements best in
/// least squares (in the plane: x, y), and its strain, the symmetric part of G.
struct AffineFit {
  Eigen::Matrix2d gradient = Eigen::Matrix2d::Zero();
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
  [[nodiscard]] Eigen::Matrix2d strain() const { return 0.5 * (gradient + gradient.transpose()); }
  double rms_residual = 0.0;  ///< of the displacements left over, m
};
/// Needs three points not on one line; throws std::invalid_argument otherwise.
AffineFit fit_affine(const std::vector<Eigen::Vector2d>& positions,
                     const std::vector<Eigen::Vector2d>& displacements);

}  // namespace cleave::physics

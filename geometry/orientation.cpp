#include "geometry/orientation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "geometry/rng.hpp"

namespace cleave::geometry {

namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2.0 * std::numbers::pi;

double wrap_two_pi(double a) {
  a = std::fmod(a, two_pi);
  if (a < 0.0) a += two_pi;
  return a >= two_pi ? 0.0 : a;  // a tiny negative angle rounds up to 2 pi
}

Eigen::Quaterniond about(const Eigen::Vector3d& axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

/// A standard normal pair by Box-Muller from two uniforms of the grain's stream.
std::array<double, 2> normal_pair(SplitMix64& rng) {
  const double radius = std::sqrt(-2.0 * std::log(1.0 - rng.uniform()));  // 1 - u in (0, 1]
  const double angle = two_pi * rng.uniform();
  return {radius * std::cos(angle), radius * std::sin(angle)};
}

Eigen::Quaterniond shoemake(SplitMix64& rng) {
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  return Eigen::Quaterniond(b * std::cos(two_pi * u3), a * std::sin(two_pi * u2),
                            a * std::cos(two_pi * u2), b * std::sin(two_pi * u3));
}

void check_spread(double spread, const char* who) {
  if (!(spread >= 0.0) || !std::isfinite(spread))
    throw std::invalid_argument(std::string(who) + ": spread must be finite and >= 0 radians");
}

/// Area of the intersection of two caps of the unit sphere with angular radii rho1, rho2 whose
/// centres are xi apart: the two sectors cut at the circles' crossing points less the spherical
/// quadrilateral of the centres and crossings, 2 [pi - gamma - a1 cos rho1 - a2 cos rho2], with
/// a1, a2 the triangle's angles at the centres and gamma the one at a crossing point.
double cap_overlap_area(double rho1, double rho2, double xi) {
  if (xi >= rho1 + rho2) return 0.0;
  const auto angle = [](double c) { return std::acos(std::clamp(c, -1.0, 1.0)); };
  const double gamma =
      angle((std::cos(xi) - std::cos(rho1) * std::cos(rho2)) / (std::sin(rho1) * std::sin(rho2)));
  const double a1 =
      angle((std::cos(rho2) - std::cos(rho1) * std::cos(xi)) / (std::sin(rho1) * std::sin(xi)));
  const double a2 =
      angle((std::cos(rho1) - std::cos(rho2) * std::cos(xi)) / (std::sin(rho2) * std::sin(xi)));
  return 2.0 * (pi - gamma - a1 * std::cos(rho1) - a2 * std::cos(rho2));
}

/// Faces of a fundamental zone in Rodrigues space: `count` planes at distance d.
struct Faces {
  double d;
  int count;
};
/// Overlapping pairs of the caps those faces cut from a sphere: `count` pairs of caps of faces
/// at distances d1, d2 whose normals are xi apart.
struct Overlaps {
  double d1, d2, xi;
  int count;
};

double cap_radius(double d, double r) {
  return std::acos(std::min(1.0, d / r));
}

/// The fraction of the sphere of radius r inside the zone: 1 - caps + pairwise overlaps.
double zone_fraction(double r, std::initializer_list<Faces> faces,
                     std::initializer_list<Overlaps> overlaps) {
  double chi = 1.0;
  for (const auto& f : faces)
    if (r > f.d) chi -= f.count * 0.5 * (1.0 - f.d / r);
  for (const auto& o : overlaps)
    if (r > o.d1 && r > o.d2)
      chi +=
          o.count * cap_overlap_area(cap_radius(o.d1, r), cap_radius(o.d2, r), o.xi) / (4.0 * pi);
  return std::max(0.0, chi);
}

const double d4 = std::numbers::sqrt2 - 1.0;               // tan(90 deg / 4): four-fold faces
const double d3 = 1.0 / std::numbers::sqrt3;               // tan(120 deg / 4): three-fold faces
const double d2 = 1.0;                                     // tan(180 deg / 4): two-fold faces
const double d6 = std::tan(pi / 12.0);                     // tan(60 deg / 4): six-fold faces
const double xi43 = std::acos(1.0 / std::numbers::sqrt3);  // between <100> and <111>

/// n-fold dihedral group: c faces at tan(pi / 2n), 2n two-fold faces every pi / n.
double dihedral_fraction(double r, int n) {
  const double dc = std::tan(pi / (2.0 * n));
  return zone_fraction(r, {{dc, 2}, {d2, 2 * n}},
                       {{dc, d2, pi / 2.0, 4 * n}, {d2, d2, pi / n, 2 * n}});
}

double dihedral_max_angle(int n) {
  // The zone's corner: on a c face and on two adjacent two-fold faces.
  const double dc = std::tan(pi / (2.0 * n));
  return 2.0 * std::atan(std::hypot(dc, 1.0 / std::cos(pi / (2.0 * n))));
}

}  // namespace

Eigen::Quaterniond canonical(const Eigen::Quaterniond& q) {
  Eigen::Quaterniond out = q.normalized();
  if (out.w() < 0.0) out.coeffs() = -out.coeffs();
  return out;
}

double rotation_angle(const Eigen::Quaterniond& q) {
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

Eigen::Quaterniond from_bunge(double phi1, double Phi, double phi2) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ(), x = Eigen::Vector3d::UnitX();
  // g^T = Rz(phi1)^T Rx(Phi)^T Rz(phi2)^T, each transpose the active rotation by +angle.
  return canonical(about(z, phi1) * about(x, Phi) * about(z, phi2));
}

std::array<double, 3> to_bunge(const Eigen::Quaterniond& q_in) {
  const Eigen::Quaterniond q = canonical(q_in);
  // q = (cos(Phi/2) cos(S), sin(Phi/2) cos(D), sin(Phi/2) sin(D), cos(Phi/2) sin(S)) with
  // S = (phi1 + phi2) / 2, D = (phi1 - phi2) / 2.
  const double s = std::hypot(q.x(), q.y()), c = std::hypot(q.w(), q.z());
  constexpr double gimbal = 1e-12;
  if (s < gimbal) return {wrap_two_pi(2.0 * std::atan2(q.z(), q.w())), 0.0, 0.0};
  if (c < gimbal) return {wrap_two_pi(2.0 * std::atan2(q.y(), q.x())), pi, 0.0};
  const double sum = std::atan2(q.z(), q.w()), diff = std::atan2(q.y(), q.x());
  return {wrap_two_pi(sum + diff), 2.0 * std::atan2(s, c), wrap_two_pi(sum - diff)};
}

std::string to_string(PointGroup group) {
  switch (group) {
    case PointGroup::cubic:
      return "cubic";
    case PointGroup::hexagonal:
      return "hexagonal";
    case PointGroup::trigonal:
      return "trigonal";
    case PointGroup::orthorhombic:
      return "orthorhombic";
    case PointGroup::none:
      return "none";
  }
  throw std::invalid_argument("unknown PointGroup value " +
                              std::to_string(static_cast<int>(group)));
}

PointGroup parse_point_group(const std::string& text) {
  for (auto g : {PointGroup::cubic, PointGroup::hexagonal, PointGroup::trigonal, PointGroup::orthorhombic,
                 PointGroup::none})
    if (text == to_string(g)) return g;
  throw std::invalid_argument("unknown point group '" + text +
                              "' (expected cubic, hexagonal, trigonal, orthorhombic or none)");
}

std::vector<Eigen::Quaterniond> symmetry_operators(PointGroup group) {
  std::vector<Eigen::Quaterniond> ops{Eigen::Quaterniond::Identity()};
  const auto add = [&](const Eigen::Vector3d& axis, double angle) {
    ops.push_back(canonical(about(axis, angle)));
  };
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  switch (group) {
    case PointGroup::cubic:
      for (const Eigen::Vector3d& a : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), z})
        for (int k = 1; k <= 3; ++k) add(a, k * pi / 2.0);
      for (const Eigen::Vector3d& a : {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(-1, 1, 1),
                                       Eigen::Vector3d(1, -1, 1), Eigen::Vector3d(1, 1, -1)})
        for (int k = 1; k <= 2; ++k) add(a, k * 2.0 * pi / 3.0);
      for (const Eigen::Vector3d& a :
           {Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(1, -1, 0), Eigen::Vector3d(1, 0, 1),
            Eigen::Vector3d(1, 0, -1), Eigen::Vector3d(0, 1, 1), Eigen::Vector3d(0, 1, -1)})
        add(a, pi);
      break;
    case PointGroup::hexagonal:
      for (int k = 1; k < 6; ++k) add(z, k * pi / 3.0);
      for (int k = 0; k < 6; ++k) add({std::cos(k * pi / 6.0), std::sin(k * pi / 6.0), 0.0}, pi);
      break;
    case PointGroup::trigonal:
      for (int k = 1; k < 3; ++k) add(z, k * 2.0 * pi / 3.0);
      for (int k = 0; k < 3; ++k)
        add({std::cos(k * 2.0 * pi / 3.0), std::sin(k * 2.0 * pi / 3.0), 0.0}, pi);
      break;
    case PointGroup::orthorhombic:
      add(z, pi);
      add({1.0, 0.0, 0.0}, pi);
      add({0.0, 1.0, 0.0}, pi);
      break;
    case PointGroup::none:
      break;
  }
  return ops;
}

double max_misorientation_angle(PointGroup group) {
  switch (group) {
    case PointGroup::cubic:
      // The truncated cube's corner (d4, d4, 1 - 2 d4): on two four-fold faces and a three-fold
      // one.
      return 2.0 * std::atan(std::sqrt(2.0 * d4 * d4 + (1.0 - 2.0 * d4) * (1.0 - 2.0 * d4)));
    case PointGroup::hexagonal:
      return dihedral_max_angle(6);
    case PointGroup::trigonal:
      return dihedral_max_angle(3);
    case PointGroup::orthorhombic:
      return dihedral_max_angle(2);
    case PointGroup::none:
      return pi;
  }
  throw std::invalid_argument("unknown PointGroup value " +
                              std::to_string(static_cast<int>(group)));
}

double misorientation_angle(const Eigen::Quaterniond& q1, const Eigen::Quaterniond& q2,
                            PointGroup group) {
  const Eigen::Quaterniond d = q1.normalized().conjugate() * q2.normalized();
  // Built once per group (thread-safe statics): this runs for every pair of grains.
  static const std::array<std::vector<Eigen::Quaterniond>, 5> groups{
      symmetry_operators(PointGroup::cubic), symmetry_operators(PointGroup::hexagonal),
      symmetry_operators(PointGroup::trigonal), symmetry_operators(PointGroup::orthorhombic),
      symmetry_operators(PointGroup::none)};
  Eigen::Quaterniond best = d;
  for (const auto& s : groups.at(static_cast<std::size_t>(group))) {
    const Eigen::Quaterniond p = d * s;
    if (std::abs(p.w()) > std::abs(best.w())) best = p;
  }
  return rotation_angle(best);
}

Eigen::Quaterniond uniform_orientation(std::uint64_t seed, std::uint64_t grain) {
  SplitMix64 rng = stream_for(seed, grain);
  return canonical(shoemake(rng));
}

Eigen::Quaterniond fibre_orientation(std::uint64_t seed, std::uint64_t grain,
                                     const Eigen::Vector3d& crystal_dir,
                                     const Eigen::Vector3d& specimen_axis, double spread) {
  check_spread(spread, "fibre_orientation");
  if (!(crystal_dir.norm() > 0.0) || !(specimen_axis.norm() > 0.0))
    throw std::invalid_argument("fibre_orientation: directions must be non-zero");
  const Eigen::Vector3d axis = specimen_axis.normalized();
  SplitMix64 rng = stream_for(seed, grain);
  const Eigen::Quaterniond align =
      Eigen::Quaterniond::FromTwoVectors(crystal_dir.normalized(), axis);
  const Eigen::Quaterniond spin = about(axis, two_pi * rng.uniform());
  if (spread == 0.0) return canonical(spin * align);

  // Tilt angle theta ~ sin(theta) exp(-theta^2 / 2 spread^2) on [0, pi], towards azimuth beta,
  // by exact rejection: a small spread proposes the 2D Gaussian tilt vector (density
  // ~ theta exp(...)) and accepts with sin(theta) / theta; a large one proposes a uniform
  // direction (density ~ sin theta) and accepts with the Gaussian factor.
  double theta = 0.0, beta = 0.0;
  for (;;) {
    if (spread <= 1.0) {
      const auto g = normal_pair(rng);
      theta = spread * std::hypot(g[0], g[1]);
      beta = std::atan2(g[1], g[0]);
      if (theta > pi) continue;
      if (theta == 0.0 || rng.uniform() * theta <= std::sin(theta)) break;
    } else {
      theta = std::acos(1.0 - 2.0 * rng.uniform());
      beta = two_pi * rng.uniform();
      if (rng.uniform() <= std::exp(-theta * theta / (2.0 * spread * spread))) break;
    }
  }
  const Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  const Eigen::Vector3d towards = std::cos(beta) * e1 + std::sin(beta) * e2;
  return canonical(about(axis.cross(towards), theta) * spin * align);
}

Eigen::Quaterniond preferred_orientation(std::uint64_t seed, std::uint64_t grain,
                                         const Eigen::Quaterniond& q0, double spread) {
  check_spread(spread, "preferred_orientation");
  if (spread == 0.0) return canonical(q0);
  SplitMix64 rng = stream_for(seed, grain);
  // omega ~ (1 - cos omega) exp(-omega^2 / 2 spread^2) on [0, pi], axis uniform, by exact
  // rejection: a small spread proposes the 3D Gaussian rotation vector (density
  // ~ omega^2 exp(...)) and accepts with (1 - cos omega) / (omega^2 / 2) <= 1; a large one
  // proposes a uniform rotation (density ~ 1 - cos omega) and accepts with the Gaussian factor.
  Eigen::Quaterniond r;
  for (;;) {
    if (spread <= 1.0) {
      const auto g01 = normal_pair(rng);
      const auto g23 = normal_pair(rng);
      const Eigen::Vector3d v = spread * Eigen::Vector3d(g01[0], g01[1], g23[0]);
      const double omega = v.norm();
      if (omega > pi) continue;
      const double half_sinc = omega == 0.0 ? 1.0 : std::sin(omega / 2.0) / (omega / 2.0);
      if (rng.uniform() > half_sinc * half_sinc) continue;
      r = omega == 0.0 ? Eigen::Quaterniond::Identity() : about(v, omega);
      break;
    } else {
      r = shoemake(rng);
      const double omega = rotation_angle(r);
      if (rng.uniform() <= std::exp(-omega * omega / (2.0 * spread * spread))) break;
    }
  }
  return canonical(r * q0.normalized());
}

double misorientation_angle_density_cubic(double omega) {
  constexpr double k = 24.0 / pi;
  const double s = std::sin(omega), c1 = 1.0 - std::cos(omega);
  if (omega < 0.0 || omega > max_misorientation_angle(PointGroup::cubic)) return 0.0;
  if (omega <= pi / 4.0) return k * c1;
  if (omega <= pi / 3.0) return k * (3.0 * d4 * s - 2.0 * c1);
  const double third = k * ((3.0 * d4 + 4.0 * d3) * s - 6.0 * c1);
  if (omega <= 2.0 * std::atan(2.0 - std::numbers::sqrt2)) return third;
  // Beyond 60.72 deg adjacent four-fold caps overlap each other and the three-fold caps.
  const double r = std::tan(omega / 2.0);
  const double rho4 = cap_radius(d4, r), rho3 = cap_radius(d3, r);
  const double overlaps =
      (12.0 * cap_overlap_area(rho4, rho4, pi / 2.0) + 24.0 * cap_overlap_area(rho4, rho3, xi43)) /
      (4.0 * pi);
  return std::max(0.0, third + k * c1 * overlaps);
}

double misorientation_angle_density(double omega, PointGroup group) {
  if (omega < 0.0 || omega > max_misorientation_angle(group)) return 0.0;
  const double r = std::tan(omega / 2.0);
  double n = 1.0, chi = 1.0;
  switch (group) {
    case PointGroup::cubic:
      n = 24.0;
      chi = zone_fraction(r, {{d4, 6}, {d3, 8}}, {{d4, d4, pi / 2.0, 12}, {d4, d3, xi43, 24}});
      break;
    case PointGroup::hexagonal:
      n = 12.0;
      chi = dihedral_fraction(r, 6);
      break;
    case PointGroup::trigonal:
      n = 6.0;
      chi = dihedral_fraction(r, 3);
      break;
    case PointGroup::orthorhombic:
      n = 4.0;
      chi = dihedral_fraction(r, 2);
      break;
    case PointGroup::none:
      break;
  }
  return n / pi * (1.0 - std::cos(omega)) * chi;
}

}  // namespace cleave::geometry

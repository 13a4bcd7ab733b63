#include "geometry/lattice.hpp"

#include <cmath>
#include <stdexcept>

namespace cleave::geometry {

namespace {
constexpr double kSqrt3 = 1.7320508075688772;
}

Eigen::Vector2d hexagon_corner(double side, int n) {
  // Corner n at 90 - 60 n degrees; App. A: (r sin(60 n), r cos(60 n)).
  const double s = side * (kSqrt3 / 2.0);
  const double h = side / 2.0;
  switch (((n % 6) + 6) % 6) {
    case 0: return {0.0, side};
    case 1: return {s, h};
    case 2: return {s, -h};
    case 3: return {0.0, -side};
    case 4: return {-s, -h};
    default: return {-s, h};
  }
}

Outline Outline::box(double a, double b, double c) {
  Outline o;
  o.kind = Kind::box;
  o.size = {a, b, c};
  return o;
}

Outline Outline::disc(double diameter, double thickness) {
  Outline o;
  o.kind = Kind::disc;
  o.size = {diameter, diameter, thickness};
  return o;
}

Outline Outline::beam(double length, double height, double thickness, double notch_width,
                      double notch_depth) {
  Outline o;
  o.kind = Kind::beam;
  o.size = {length, height, thickness};
  o.notch_width = notch_width;
  o.notch_depth = notch_depth;
  return o;
}

bool Outline::contains(const Eigen::Vector3d& p, double tol) const {
  for (int d = 0; d < 3; ++d) {
    if (p[d] < -tol || p[d] > size[d] + tol) return false;
  }
  switch (kind) {
    case Kind::box: return true;
    case Kind::disc: {
      const double R = size.x() / 2.0;
      const double dx = p.x() - R, dy = p.y() - R;
      return std::sqrt(dx * dx + dy * dy) <= R + tol;
    }
    case Kind::beam: {
      if (notch_width <= 0.0 || notch_depth <= 0.0) return true;
      const double half = notch_width / 2.0, mid = size.x() / 2.0;
      // The notch is the open slot |x - mid| < half, y < depth: points strictly inside it
      // are outside the beam; its boundary belongs to the beam.
      const bool in_notch = std::abs(p.x() - mid) < half - tol && p.y() < notch_depth - tol;
      return !in_notch;
    }
  }
  return false;
}

bool Outline::contains_cell(const Eigen::Vector3d& c, double r, double t) const {
  const double tol = 1e-9 * std::max(r, t);
  for (int n = 0; n < 6; ++n) {
    const Eigen::Vector2d q = hexagon_corner(r, n);
    for (double dz : {-t / 2.0, t / 2.0}) {
      if (!contains({c.x() + q.x(), c.y() + q.y(), c.z() + dz}, tol)) return false;
    }
  }
  if (kind == Kind::beam && notch_width > 0.0 && notch_depth > 0.0) {
    // The beam is not convex: corners outside the slot do not prove the cell misses it.
    // Separate the hexagon from the slot rectangle [mid-half, mid+half] x [-inf, depth]
    // along the hexagon's three side-face normals and the two axes.
    const double mid = size.x() / 2.0, half = notch_width / 2.0;
    const double apothem = r * (kSqrt3 / 2.0);
    // x axis: the hexagon spans c.x +- apothem; y axis: c.y +- r.
    if (c.x() + apothem <= mid - half + tol || c.x() - apothem >= mid + half - tol) return true;
    if (c.y() - r >= notch_depth - tol) return true;
    // Side-face normals at 0, 60, 120 degrees; the slot extends to y = -inf, so along a
    // normal with a y component the slot is unbounded on one side.
    for (double deg : {60.0, 120.0}) {
      const double a = deg * M_PI / 180.0;
      const Eigen::Vector2d nrm(std::cos(a), std::sin(a));  // ny > 0
      const double hc = nrm.dot(c.head<2>());
      // The slot's largest projection is at its top corners (y = depth).
      const double slot_max = std::max(nrm.dot(Eigen::Vector2d(mid - half, notch_depth)),
                                       nrm.dot(Eigen::Vector2d(mid + half, notch_depth)));
      if (hc - apothem >= slot_max - tol) return true;
    }
    return false;
  }
  return true;
}

std::vector<LatticeSite> honeycomb_sites(double r, double t, const Outline& outline,
                                         KeepRule rule) {
  if (!(r > 0.0) || !(t > 0.0)) {
    throw std::invalid_argument("honeycomb_sites: r and t must be positive");
  }
  const double h = 1.5 * r;
  const Eigen::Vector3d& L = outline.size;
  // Generous index bounds; the outline test decides what is kept.
  const int i_max = static_cast<int>(std::ceil(L.x() / (kSqrt3 * r))) + 1;
  const int j_max = static_cast<int>(std::ceil(L.y() / h)) + 1;
  const int k_max = static_cast<int>(std::ceil(L.z() / t)) + 1;

  std::vector<LatticeSite> sites;
  for (int k = 1; k <= k_max; ++k) {
    const char plane = (k % 2 == 1) ? 'A' : 'B';
    const double z = t / 2.0 + (k - 1) * t;
    // Table 2.1: plane A rows at y = r + (j-1)h (j >= 1), plane B rows at y = r + j h.
    // Row type alternates with the row's height: row 1 at y = r + (even multiple of h).
    const int j_first = (plane == 'A') ? 1 : 0;
    for (int j = j_first; j <= j_max; ++j) {
      const int steps = (plane == 'A') ? j - 1 : j;  // y = r + steps h
      const double y = r + steps * h;
      // Plane A: row 1 on even steps. Plane B is shifted: row 1 on odd steps (table 2.1's
      // B row 1 at y = r + j h with j = 1).
      const bool row1 = (plane == 'A') ? (steps % 2 == 0) : (steps % 2 == 1);
      for (int i = 1; i <= i_max; ++i) {
        const double x = row1 ? kSqrt3 * i * r : (kSqrt3 / 2.0) * (2 * i - 1) * r;
        const Eigen::Vector3d c(x, y, z);
        const bool keep = (rule == KeepRule::cell_inside)
                              ? outline.contains_cell(c, r, t)
                              : outline.contains(c, 1e-9 * std::max(r, t));
        if (!keep) continue;
        sites.push_back(LatticeSite{c, plane, row1 ? 1 : 2, i, j, k});
      }
    }
  }
  return sites;
}

}  // namespace cleave::geometry

// Persistent contact manifolds (ContactManifold, narrow_phase.hpp): a touching pair's
// contacts carried with its two bodies while they move less than the manifold's margin.

#include <algorithm>
#include <cmath>
#include <tuple>

#include "physics/dem/narrow_phase.hpp"

namespace cleave::physics {

void capture_manifold(const PosedShape& a, const PosedShape& b,
                      const std::vector<FeatureContact>& found, double margin, ContactManifold& m) {
  const Eigen::Matrix3d at = a.rotation.transpose(), bt = b.rotation.transpose();
  m.entries.clear();
  for (const FeatureContact& fc : found) {
    ContactManifold::Entry e;
    e.feature_a = fc.feature_a;
    e.feature_b = fc.feature_b;
    e.point_a = at * (fc.contact.point - a.centre);
    e.point_b = bt * (fc.contact.point - b.centre);
    e.normal_a = at * fc.contact.normal;
    e.penetration = fc.contact.penetration;
    m.entries.push_back(e);
  }
  // In feature order, as the world lists a pair's contacts: carried ones need no sort.
  std::sort(m.entries.begin(), m.entries.end(), [](const auto& x, const auto& y) {
    return std::tie(x.feature_a, x.feature_b) < std::tie(y.feature_a, y.feature_b);
  });
  m.offset = at * (b.centre - a.centre);
  m.turn = a.orientation.conjugate() * b.orientation;
  m.lever = b.primitives->bounding_radius;  // the dilation included
  m.margin = margin;
}

bool manifold_holds(const PosedShape& a, const PosedShape& b, const ContactManifold& m) {
  if (!(m.margin > 0.0)) return false;
  const Eigen::Vector3d offset = a.rotation.transpose() * (b.centre - a.centre);
  const Eigen::Quaterniond turn = a.orientation.conjugate() * b.orientation;
  // A unit vector of B turned by theta relative to A moves 2 sin(theta/2) <= 2 |dq|.
  const double dq = turn_between(turn, m.turn);
  const double moved = (offset - m.offset).norm() + 2.0 * m.lever * dq;
  return moved < 0.5 * m.margin;
}

bool manifold_contacts(const PosedShape& a, const PosedShape& b, const ContactManifold& m,
                       std::vector<FeatureContact>& out) {
  if (!manifold_holds(a, b, m)) return false;
  for_carried_contacts(a, b, m, [&](std::uint32_t fa, std::uint32_t fb, const PrimitiveContact& c) {
    out.push_back({fa, fb, c});
  });
  return true;
}

}  // namespace cleave::physics

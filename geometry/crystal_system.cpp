#include "geometry/crystal_system.hpp"

#include <cctype>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cleave::geometry {

std::string to_string(CrystalSystem system) {
  switch (system) {
    case CrystalSystem::cubic: return "cubic";
    case CrystalSystem::hexagonal: return "hexagonal";
    case CrystalSystem::trigonal: return "trigonal";
    case CrystalSystem::orthorhombic: return "orthorhombic";
  }
  return "?";
}

CrystalSystem parse_crystal_system(const std::string& text) {
  for (CrystalSystem s : {CrystalSystem::cubic, CrystalSystem::hexagonal, CrystalSystem::trigonal,
                          CrystalSystem::orthorhombic}) {
    if (text == to_string(s)) return s;
  }
  throw std::invalid_argument("unknown crystal system '" + text +
                              "' (expected cubic, hexagonal, trigonal or orthorhombic)");
}

PointGroup point_group(CrystalSystem system) {
  switch (system) {
    case CrystalSystem::cubic: return PointGroup::cubic;
    case CrystalSystem::hexagonal: return PointGroup::hexagonal;
    case CrystalSystem::trigonal: return PointGroup::trigonal;
    case CrystalSystem::orthorhombic: return PointGroup::orthorhombic;
  }
  return PointGroup::none;
}

namespace {
bool four_indices(CrystalSystem s) {
  return s == CrystalSystem::hexagonal || s == CrystalSystem::trigonal;
}

/// The direct lattice vectors as columns (a = 1).
Eigen::Matrix3d direct_basis(const CrystalLattice& lattice) {
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  switch (lattice.system) {
    case CrystalSystem::cubic:
      a = Eigen::Matrix3d::Identity();
      break;
    case CrystalSystem::hexagonal:
    case CrystalSystem::trigonal:
      a.col(0) = Eigen::Vector3d(1.0, 0.0, 0.0);
      a.col(1) = Eigen::Vector3d(-0.5, std::sqrt(3.0) / 2.0, 0.0);
      a.col(2) = Eigen::Vector3d(0.0, 0.0, lattice.c_over_a);
      break;
    case CrystalSystem::orthorhombic:
      a.diagonal() = Eigen::Vector3d(1.0, lattice.b_over_a, lattice.c_over_a);
      break;
  }
  return a;
}
}  // namespace

MillerFamily parse_miller_family(const std::string& text, CrystalSystem system) {
  const std::size_t want = four_indices(system) ? 4 : 3;
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument("plane family '" + text + "': " + why);
  };
  if (text.size() < 2 || text.front() != '{' || text.back() != '}') {
    fail("expected the indices in braces, e.g. " +
         std::string(want == 4 ? "\"{10-12}\"" : "\"{110}\""));
  }
  std::vector<int> idx;
  for (std::size_t i = 1; i + 1 < text.size(); ++i) {
    int sign = 1;
    if (text[i] == '-') {
      sign = -1;
      ++i;
    }
    if (i + 1 >= text.size() || !std::isdigit(static_cast<unsigned char>(text[i]))) {
      fail("expected single digits, each optionally preceded by '-'");
    }
    idx.push_back(sign * (text[i] - '0'));
  }
  if (idx.size() != want) {
    fail("a " + to_string(system) + " crystal's planes take " + std::to_string(want) +
         (want == 4 ? " Miller-Bravais indices {hkil}" : " Miller indices {hkl}") + ", found " +
         std::to_string(idx.size()));
  }
  MillerFamily f;
  f.text = text;
  f.h = idx[0];
  f.k = idx[1];
  f.l = idx.back();
  if (want == 4 && idx[2] != -(idx[0] + idx[1])) {
    fail("the third index must be -(h + k) = " + std::to_string(-(idx[0] + idx[1])));
  }
  if (f.h == 0 && f.k == 0 && f.l == 0) fail("the indices must not all be zero");
  return f;
}

Eigen::Vector3d plane_normal(const CrystalLattice& lattice, const MillerFamily& family) {
  // Reciprocal vectors are the rows of the direct basis' inverse: n = A^-T (h, k, l).
  const Eigen::Matrix3d reciprocal = direct_basis(lattice).inverse().transpose();
  return (reciprocal * Eigen::Vector3d(family.h, family.k, family.l)).normalized();
}

std::vector<Eigen::Vector3d> family_normals(const CrystalLattice& lattice,
                                            const MillerFamily& family) {
  const Eigen::Vector3d n = plane_normal(lattice, family);
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Quaterniond& r : symmetry_operators(point_group(lattice.system))) {
    const Eigen::Vector3d m = (r * n).normalized();
    bool seen = false;
    for (const auto& o : out) seen = seen || std::abs(o.dot(m)) > 1.0 - 1e-12;
    if (!seen) out.push_back(m);
  }
  return out;
}

std::vector<int> plane_families(const CrystalDef& crystal) {
  std::vector<int> out;
  for (std::size_t f = 0; f < crystal.families.size(); ++f) {
    const CleavageFamilyDef& def = crystal.families[f];
    const std::size_t n = family_normals(crystal.lattice, def.family).size() *
                          static_cast<std::size_t>(std::max(def.planes_per_variant, 1));
    out.insert(out.end(), n, static_cast<int>(f));
  }
  return out;
}

CleavagePlanes crystal_cleavage_planes(const ExactPolyhedron& shape, const CrystalDef& crystal,
                                       const Eigen::Quaterniond& orientation) {
  CleavagePlanes out;
  const std::vector<Eigen::Vector3d> vertices = shape.vertices_approx();
  const Eigen::Matrix3d r = orientation.normalized().toRotationMatrix();
  for (std::size_t f = 0; f < crystal.families.size(); ++f) {
    const CleavageFamilyDef& def = crystal.families[f];
    const int n = std::max(def.planes_per_variant, 1);
    for (const Eigen::Vector3d& crystal_normal : family_normals(crystal.lattice, def.family)) {
      const Eigen::Vector3d normal = r * crystal_normal;
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& v : vertices) {
        lo = std::min(lo, v.dot(normal));
        hi = std::max(hi, v.dot(normal));
      }
      for (int i = 1; i <= n; ++i) {
        out.planes.push_back(ExactPlane::from_normal_offset(normal, lo + (hi - lo) * i / (n + 1)));
        out.family.push_back(static_cast<int>(f));
      }
    }
  }
  return out;
}

}  // namespace cleave::geometry

#include "physics/dem/cell_control.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace cleave::physics {

void CellControl::check(const PeriodicCell& cell) {
  if (!cell.vectors().allFinite() || !(cell.volume() > 0.0) || !cell.origin().allFinite())
    throw std::invalid_argument("set_cell: the cell vectors must be finite and span a volume");
  if (!cell.any_periodic()) throw std::invalid_argument("set_cell: no axis is periodic");
}

void CellControl::set_velocity_gradient(const Eigen::Matrix3d& l) {
  if (!on_) throw std::logic_error("set_velocity_gradient: there is no periodic cell");
  if (!l.allFinite()) throw std::invalid_argument("set_velocity_gradient: not finite");
  cell_.set_velocity_gradient(l);
}

void CellControl::begin_step(const Eigen::Matrix3d& gradient, const Eigen::Matrix3d* sigma) {
  gradient_ = gradient;
  if (sigma != nullptr) {
    // Berendsen: the axes left free relax their mean normal stress (a cell in tension
    // shrinks, one in compression grows).
    const Eigen::Matrix3d set = cell_.velocity_gradient();
    for (int k = 0; k < 3; ++k) {
      if (cell_.periodic(k) && set(k, k) == 0.0)
        gradient_(k, k) -= (*sigma)(k, k) / (stress_modulus_ * stress_tau_);
    }
  }
  moving_ = !gradient_.isZero(0.0);
}

void CellControl::deform(std::vector<BodyState>& states, const std::vector<BodyInfo>& infos,
                         double h) {
  if (!moving_) return;
  const Eigen::Matrix3d step = h * gradient_;
  const auto slots = static_cast<std::ptrdiff_t>(states.size());
  for (std::ptrdiff_t i = 0; i < slots; ++i) {
    if (infos[i].alive) states[i].x += step * (states[i].x - cell_.origin());
  }
  cell_.deform(step);
}

std::vector<Eigen::Vector3i> CellControl::wrap(std::vector<BodyState>& states,
                                               const std::vector<BodyInfo>& infos) const {
  // Which bodies leave, by how many cells.
  std::vector<Eigen::Vector3i> moved;
  bool any = false;
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (!infos[i].alive) continue;
    const Eigen::Vector3i m = cell_.outside(states[i].x);
    if (m.isZero()) continue;
    if (!any) moved.assign(states.size(), Eigen::Vector3i::Zero());
    any = true;
    moved[i] = m;
    states[i].x -= cell_.shift(m);
  }
  return moved;
}

void CellControl::find_pairs(NeighbourSearch& search, const std::vector<BoundingSphere>& spheres,
                             double margin, std::vector<BodyPair>& pairs) const {
  if (!on_) {
    search.find_pairs(spheres, margin, pairs);
    return;
  }
  // The bodies in the master cell and, near its periodic faces, their images across them:
  // every pair within reach appears once as some pair of these, each named by its owners.
  double largest = 0.0;
  for (const BoundingSphere& s : spheres) largest = std::max(largest, s.radius);
  const double reach = 2.0 * largest + margin;
  for (int k = 0; k < 3; ++k) {
    if (cell_.periodic(k) && !(cell_.width(k) > 2.0 * reach)) {
      throw std::runtime_error(
          "periodic cell too small: " + std::to_string(cell_.width(k)) + " m across axis " +
          std::to_string(k) + ", a pair reaches " + std::to_string(reach) +
          " m (2 x the largest bounding radius + the skin); the cell must be over twice that");
    }
  }
  std::vector<BoundingSphere> all(spheres.begin(), spheres.end());
  std::vector<std::uint32_t> owner(spheres.size());
  for (std::uint32_t i = 0; i < owner.size(); ++i) owner[i] = i;
  const Eigen::Vector3i lo(cell_.periodic(0) ? -1 : 0, cell_.periodic(1) ? -1 : 0,
                           cell_.periodic(2) ? -1 : 0);
  const Eigen::Vector3i hi = -lo;
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const Eigen::Vector3d home = spheres[i].centre - cell_.shift(cell_.outside(spheres[i].centre));
    all[i].centre = home;
    for (int x = lo[0]; x <= hi[0]; ++x) {
      for (int y = lo[1]; y <= hi[1]; ++y) {
        for (int z = lo[2]; z <= hi[2]; ++z) {
          if (x == 0 && y == 0 && z == 0) continue;
          const Eigen::Vector3d ghost = home + cell_.shift({x, y, z});
          const Eigen::Vector3d s = cell_.reduced(ghost);
          bool near = true;
          for (int k = 0; k < 3 && near; ++k) {
            const double band = reach / cell_.width(k);
            if (cell_.periodic(k)) near = s[k] > -band && s[k] < 1.0 + band;
          }
          if (!near) continue;
          all.push_back({ghost, spheres[i].radius});
          owner.push_back(i);
        }
      }
    }
  }
  std::vector<BodyPair> found;
  search.find_pairs(all, margin, found);
  pairs.clear();
  for (const auto& [p, q] : found) {
    const std::uint32_t i = owner[p], j = owner[q];
    if (i != j) pairs.emplace_back(std::min(i, j), std::max(i, j));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

void CellControl::shifted_copy(const PosedShape& posed, const Eigen::Vector3d& shift,
                               PosedShape& out) {
  out = posed;
  out.centre += shift;
  for (Eigen::Vector3d& v : out.vertices) v += shift;
  out.lo += shift;
  out.hi += shift;
  const std::size_t stride = out.plane_stride();
  for (std::size_t f = 0; f < out.faces; ++f)
    out.planes[3 * stride + f] += out.face_normal(f).dot(shift);
}

}  // namespace cleave::physics

// A shape posed for the narrow phase: its frame, vertices and face planes in world axes
// (PosedShape, narrow_phase.hpp).

#include <algorithm>
#include <cmath>

#include "physics/dem/narrow_phase.hpp"

namespace cleave::physics {

void PosedShape::update(const RigidShape& shape, const BodyState& state) {
  update_frame(shape, state);
  update_geometry();
}

void PosedShape::update_frame(const RigidShape& shape, const BodyState& state) {
  if (primitives != nullptr) {
    travel += (state.x - centre).norm();
    turn += turn_between(state.q, orientation);
  }
  primitives = &shape.primitives;
  centre = state.x;
  orientation = state.q;
  radius = shape.primitives.dilation_radius;
  rotation = state.q.toRotationMatrix();
}

void PosedShape::update_vertices() {
  // centre + R v and the box in scalars, each operation Eigen's (its 3x3 product sums rows
  // 0 and 1 left to right, in one SSE pair, and row 2 as (a + (b + c)); cwiseMin/Max are
  // std::min/max by component): the same bits, without Eigen reading each vertex and the box
  // back as 16-byte pairs just stored as 8-byte halves.
  const Eigen::Matrix3d& R = rotation;
  const double r00 = R(0, 0), r01 = R(0, 1), r02 = R(0, 2), r10 = R(1, 0), r11 = R(1, 1),
               r12 = R(1, 2), r20 = R(2, 0), r21 = R(2, 1), r22 = R(2, 2);
  const double cx = centre.x(), cy = centre.y(), cz = centre.z();
  const auto& p = *primitives;
  vertices.resize(p.vertices.size());
  double lx = cx, ly = cy, lz = cz, hx = cx, hy = cy, hz = cz;
  for (std::size_t i = 0; i < p.vertices.size(); ++i) {
    const double v0 = p.vertices[i].x(), v1 = p.vertices[i].y(), v2 = p.vertices[i].z();
    const double x = cx + ((r00 * v0 + r01 * v1) + r02 * v2);
    const double y = cy + ((r10 * v0 + r11 * v1) + r12 * v2);
    const double z = cz + (r20 * v0 + (r21 * v1 + r22 * v2));
    vertices[i] = {x, y, z};
    lx = std::min(lx, x);
    ly = std::min(ly, y);
    lz = std::min(lz, z);
    hx = std::max(hx, x);
    hy = std::max(hy, y);
    hz = std::max(hz, z);
  }
  lo = {lx, ly, lz};
  hi = {hx, hy, hz};
}

void PosedShape::update_geometry() {
  update_vertices();
  const Eigen::Matrix3d& R = rotation;
  const auto& p = *primitives;
  const std::size_t nf = p.faces.size(), stride = (nf + 1) & ~std::size_t{1};
  faces = nf;
  if (planes.size() != 4 * stride) planes.assign(4 * stride, 0.0);  // the padding stays 0
  for (std::size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d n = R * p.faces[f].normal;
    for (int k = 0; k < 3; ++k) planes[k * stride + f] = n[k];
    planes[3 * stride + f] = n.dot(vertices[p.faces[f].vertices[0]]);
  }
}

}  // namespace cleave::physics

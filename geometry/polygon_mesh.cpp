#include "geometry/polygon_mesh.hpp"

#include <map>
#include <set>
#include <utility>

namespace cleave::geometry {

std::size_t PolygonMesh::edge_count() const {
  std::set<std::pair<int, int>> edges;
  for (const auto& f : faces) {
    for (std::size_t i = 0; i < f.size(); ++i) {
      int a = f[i], b = f[(i + 1) % f.size()];
      edges.emplace(std::min(a, b), std::max(a, b));
    }
  }
  return edges.size();
}

PolygonMesh PolygonMesh::triangulated() const {
  PolygonMesh out;
  out.name = name;
  out.vertices = vertices;
  for (const auto& f : faces) {
    for (std::size_t i = 1; i + 1 < f.size(); ++i) out.faces.push_back({f[0], f[i], f[i + 1]});
  }
  return out;
}

double PolygonMesh::signed_volume() const {
  double six_v = 0.0;
  for (const auto& f : faces) {
    for (std::size_t i = 1; i + 1 < f.size(); ++i) {
      const Eigen::Vector3d& a = vertices[f[0]];
      const Eigen::Vector3d& b = vertices[f[i]];
      const Eigen::Vector3d& c = vertices[f[i + 1]];
      six_v += a.dot(b.cross(c));
    }
  }
  return six_v / 6.0;
}

bool PolygonMesh::is_closed_and_consistently_oriented() const {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : faces) {
    if (f.size() < 3) return false;
    for (std::size_t i = 0; i < f.size(); ++i) {
      ++directed[{f[i], f[(i + 1) % f.size()]}];
    }
  }
  for (const auto& [e, n] : directed) {
    if (n != 1) return false;
    auto it = directed.find({e.second, e.first});
    if (it == directed.end() || it->second != 1) return false;
  }
  return !directed.empty();
}

}  // namespace cleave::geometry

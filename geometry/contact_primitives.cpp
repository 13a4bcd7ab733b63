#include "geometry/contact_primitives.hpp"

#include <map>
#include <stdexcept>

#include <Eigen/Geometry>

namespace cleave::geometry {

ContactPrimitives make_contact_primitives(const PolygonMesh& shape, const Eigen::Vector3d& centroid,
                                          double dilation_radius) {
  if (!(dilation_radius >= 0.0)) throw std::invalid_argument("dilation radius must be >= 0");
  if (!shape.is_closed_and_consistently_oriented()) {
    throw std::invalid_argument("contact primitives need a closed, consistently oriented mesh");
  }
  ContactPrimitives out;
  out.origin = centroid;
  out.dilation_radius = dilation_radius;
  out.vertices.reserve(shape.vertices.size());
  double reach = 0.0;
  for (const auto& v : shape.vertices) {
    out.vertices.push_back(v - centroid);
    reach = std::max(reach, out.vertices.back().norm());
  }
  out.bounding_radius = reach + dilation_radius;

  std::map<std::pair<int, int>, int> edge_of;  // undirected edge -> index in out.edges
  for (std::size_t f = 0; f < shape.faces.size(); ++f) {
    const auto& loop = shape.faces[f];
    ContactFace face;
    face.vertices = loop;
    // Newell's method: area vector and area centroid of a planar polygon.
    Eigen::Vector3d area_vec = Eigen::Vector3d::Zero();
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    const Eigen::Vector3d& p0 = out.vertices[loop[0]];
    for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
      const Eigen::Vector3d& p1 = out.vertices[loop[i]];
      const Eigen::Vector3d& p2 = out.vertices[loop[i + 1]];
      const Eigen::Vector3d tri = 0.5 * (p1 - p0).cross(p2 - p0);
      area_vec += tri;
      weighted += tri.norm() * (p0 + p1 + p2) / 3.0;
      out.triangles.push_back(ContactTriangle{{loop[0], loop[i], loop[i + 1]}, static_cast<int>(f)});
    }
    face.area = area_vec.norm();
    face.normal = area_vec / face.area;
    face.centroid = weighted / face.area;
    face.offset = face.normal.dot(face.centroid);
    out.faces.push_back(std::move(face));

    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto [it, fresh] = edge_of.try_emplace(key, static_cast<int>(out.edges.size()));
      if (fresh) out.edges.push_back(ContactEdge{key.first, key.second, -1, -1});
      // The face that runs a -> b with a < b is on the edge's left.
      (a < b ? out.edges[it->second].left_face : out.edges[it->second].right_face) =
          static_cast<int>(f);
    }
  }
  finish_primitives(out);
  return out;
}

bool finish_primitives(ContactPrimitives& p) {
  p.edge_units.clear();
  p.edge_lengths.clear();
  for (const auto& e : p.edges) {
    const Eigen::Vector3d d = p.vertices[e.b] - p.vertices[e.a];
    p.edge_lengths.push_back(d.norm());
    p.edge_units.push_back(d / p.edge_lengths.back());
  }
  double spread = 0.0;
  for (const auto& e : p.edges) {
    const auto faces = static_cast<int>(p.faces.size());
    if (e.left_face < 0 || e.right_face < 0 || e.left_face >= faces || e.right_face >= faces) continue;
    spread = std::max(spread, -p.faces[e.left_face].normal.dot(p.faces[e.right_face].normal));
  }
  p.edge_cone_spread = spread + 1e-6;
  std::map<std::pair<int, int>, int> edge_of;
  for (std::size_t e = 0; e < p.edges.size(); ++e) edge_of[{p.edges[e].a, p.edges[e].b}] = static_cast<int>(e);
  bool complete = true;
  for (auto& face : p.faces) {
    face.rim.clear();
    const auto& loop = face.vertices;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      const auto it = edge_of.find({std::min(a, b), std::max(a, b)});
      complete = complete && it != edge_of.end();
      face.rim.push_back(it != edge_of.end() ? it->second : -1);
    }
  }
  return complete;
}

}  // namespace cleave::geometry

// Transgranular fracture, chapter 3: consistent face tractions (sec. 3.2, eq. 3.15), tractions
// on a potential crack plane (sec. 3.3, eqs 3.20-3.21) and the fracture criterion (sec. 3.4,
// eqs 3.22-3.25). Expected values are closed forms of plane sections and beams.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <vector>

#include "physics/transgranular/crack_plane.hpp"
#include "physics/transgranular/face_traction.hpp"
#include "physics/transgranular/fracture_criterion.hpp"
#include "physics/transgranular/transgranular.hpp"

using namespace cleave::physics;
using Eigen::Vector3d;

namespace {

/// A tilted, shifted face frame, so nothing lines up with the world axes by accident.
struct Frame {
  Vector3d c, x, y, n;
};

Frame tilted_frame() {
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  return {Vector3d(0.3e-3, -0.7e-3, 1.1e-3), r.col(0), r.col(1), r.col(2)};
}

/// Rectangle of width b along f.x and height h along f.y centred on f.c, counter-clockwise
/// about f.n.
std::vector<Vector3d> rectangle(const Frame& f, double b, double h) {
  return {f.c - b / 2 * f.x - h / 2 * f.y, f.c + b / 2 * f.x - h / 2 * f.y,
          f.c + b / 2 * f.x + h / 2 * f.y, f.c - b / 2 * f.x + h / 2 * f.y};
}

/// Regular hexagon of side s centred on f.c, first vertex along f.x, counter-clockwise.
std::vector<Vector3d> hexagon(const Frame& f, double s) {
  std::vector<Vector3d> v;
  for (int k = 0; k < 6; ++k) {
    const double a = k * M_PI / 3.0;
    v.push_back(f.c + s * (std::cos(a) * f.x + std::sin(a) * f.y));
  }
  return v;
}

/// Cell-centred nu x nv grid on the rectangle centre +- hu u +- hv v; each point gets
/// traction(point) times its cell's area.
std::vector<PointForce> grid(const Vector3d& centre, const Vector3d& u, double hu,
                             const Vector3d& v, double hv, int nu, int nv,
                             const std::function<Vector3d(const Vector3d&)>& traction) {
  std::vector<PointForce> out;
  const double da = (2 * hu / nu) * (2 * hv / nv);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const Vector3d p =
          centre + (-hu + (i + 0.5) * 2 * hu / nu) * u + (-hv + (j + 0.5) * 2 * hv / nv) * v;
      out.push_back({p, traction(p) * da});
    }
  }
  return out;
}

void expect_vec_near(const Vector3d& a, const Vector3d& b, double tol) {
  EXPECT_NEAR(a.x(), b.x(), tol);
  EXPECT_NEAR(a.y(), b.y(), tol);
  EXPECT_NEAR(a.z(), b.z(), tol);
}

const double kB = 2e-3;  // rectangle face: 2 mm along x
const double kH = 1e-3;  //                 1 mm along y

}  // namespace

// --- Face geometry (eq. 3.13) -------------------------------------------------------------

TEST(FaceGeometry, RectangleMatchesClosedForms) {
  const Frame f = tilted_frame();
  const auto poly = rectangle(f, kB, kH);
  const FaceGeometry g = face_geometry(poly, f.n, f.x);
  EXPECT_NEAR(g.area, kB * kH, 1e-18);
  // Eq. 3.13: I_xx = integral x^2 dA (x along the 2 mm side).
  EXPECT_NEAR(g.i_xx, kH * kB * kB * kB / 12, 1e-26);
  EXPECT_NEAR(g.i_yy, kB * kH * kH * kH / 12, 1e-26);
  EXPECT_NEAR(g.i_xy, 0.0, 1e-26);
  EXPECT_EQ(g.q_x, 0.0);
  EXPECT_EQ(g.q_y, 0.0);
  expect_vec_near(g.origin, f.c, 1e-15);
  expect_vec_near(g.normal, f.n, 1e-15);
  expect_vec_near(g.x_axis, f.x, 1e-15);
  expect_vec_near(g.y_axis, f.y, 1e-15);

  // Clockwise vertices give the same moments.
  const std::vector<Vector3d> cw(poly.rbegin(), poly.rend());
  const FaceGeometry gr = face_geometry(cw, f.n, f.x);
  EXPECT_NEAR(gr.area, kB * kH, 1e-18);
  EXPECT_NEAR(gr.i_xx, kH * kB * kB * kB / 12, 1e-26);

  // Axes turned by theta in the plane: I_xx = cos^2 Iu + sin^2 Iv, I_xy = sc (Iv - Iu).
  const double th = 0.3, co = std::cos(th), si = std::sin(th);
  const double iu = kH * kB * kB * kB / 12, iv = kB * kH * kH * kH / 12;
  const FaceGeometry gt = face_geometry(poly, f.n, co * f.x + si * f.y);
  EXPECT_NEAR(gt.i_xx, co * co * iu + si * si * iv, 1e-26);
  EXPECT_NEAR(gt.i_yy, si * si * iu + co * co * iv, 1e-26);
  EXPECT_NEAR(gt.i_xy, si * co * (iv - iu), 1e-26);

  // Newell's normal and the first edge as x axis.
  const FaceGeometry gn = face_geometry(poly);
  expect_vec_near(gn.normal, f.n, 1e-12);
  expect_vec_near(gn.x_axis, f.x, 1e-12);
  EXPECT_NEAR(gn.i_xx, iu, 1e-26);
}

TEST(FaceGeometry, RegularHexagonMatchesClosedForms) {
  const Frame f = tilted_frame();
  const double s = 0.6e-3;
  const auto poly = hexagon(f, s);
  const double area = 1.5 * std::sqrt(3.0) * s * s;
  const double inertia = 5.0 * std::sqrt(3.0) / 16.0 * s * s * s * s;  // any centroidal axis
  for (double th : {0.0, 0.2, 1.1}) {
    const FaceGeometry g = face_geometry(poly, f.n, std::cos(th) * f.x + std::sin(th) * f.y);
    EXPECT_NEAR(g.area, area, 1e-18);
    EXPECT_NEAR(g.i_xx, inertia, 1e-27);
    EXPECT_NEAR(g.i_yy, inertia, 1e-27);
    EXPECT_NEAR(g.i_xy, 0.0, 1e-27);
    expect_vec_near(g.origin, f.c, 1e-15);
  }
}

// --- Consistent face tractions (eqs 3.14-3.19) --------------------------------------------

TEST(FaceTraction, UniformPressureGivesForceOverArea) {
  const Frame f = tilted_frame();
  const FaceGeometry g = face_geometry(rectangle(f, kB, kH), f.n, f.x);
  const double p = 3e6;  // 3 MPa pushing on the face
  const auto forces = grid(f.c, f.x, kB / 2, f.y, kH / 2, 8, 4,
                           [&](const Vector3d&) { return Vector3d(-p * f.n); });
  const FaceTractions t = face_tractions(g, forces);
  const double total = -p * kB * kH;  // F . n
  EXPECT_NEAR(t.t_o, total / (kB * kH), 1e-6);
  EXPECT_NEAR(t.t_o, -p, 1e-6);
  // C1, C2 in Pa/m: a gradient of 1e-3 Pa/mm would be noise.
  EXPECT_NEAR(t.c1, 0.0, 1e-3);
  EXPECT_NEAR(t.c2, 0.0, 1e-3);
  EXPECT_NEAR(t.t_x, 0.0, 1e-6);
  EXPECT_NEAR(t.t_y, 0.0, 1e-6);
  EXPECT_NEAR(t.m_z, 0.0, 1e-15);

  // An equal shear force at each point is a uniform shear traction (eq. 3.14a-b).
  const auto shear = grid(f.c, f.x, kB / 2, f.y, kH / 2, 8, 4,
                          [&](const Vector3d&) { return Vector3d(1e6 * f.x - 2e6 * f.y); });
  const FaceTractions ts = face_tractions(g, shear);
  EXPECT_NEAR(ts.t_x, 1e6, 1e-6);
  EXPECT_NEAR(ts.t_y, -2e6, 1e-6);
  EXPECT_NEAR(ts.t_s(), std::sqrt(5.0) * 1e6, 1e-6);
  EXPECT_NEAR(ts.t_o, 0.0, 1e-6);
}

TEST(FaceTraction, PureBendingGivesMomentOverInertia) {
  const Frame f = tilted_frame();
  const FaceGeometry g = face_geometry(rectangle(f, kB, kH), f.n, f.x);
  const double k = 1e9;  // N/m per point: f = k x, a linear, self-balanced set
  for (int axis = 0; axis < 2; ++axis) {
    const Vector3d dir = axis == 0 ? f.x : f.y;
    const auto forces = grid(f.c, f.x, kB / 2, f.y, kH / 2, 10, 6, [&](const Vector3d& q) {
      return Vector3d(k * (q - f.c).dot(dir) * f.n);
    });
    double m = 0.0, resultant = 0.0;  // the applied bending moment, sum of (arm . dir) f_n
    for (const auto& pf : forces) {
      m += (pf.point - f.c).dot(dir) * pf.force.dot(f.n);
      resultant += pf.force.dot(f.n);
    }
    ASSERT_NEAR(resultant, 0.0, 1e-12);
    const FaceTractions t = face_tractions(g, forces);
    const double ixx = kH * kB * kB * kB / 12, iyy = kB * kH * kH * kH / 12;
    EXPECT_NEAR(t.t_o, 0.0, 1e-6);
    if (axis == 0) {
      EXPECT_NEAR(t.c1, m / ixx, 1e-9 * std::abs(m / ixx));
      EXPECT_NEAR(t.c2, 0.0, 1e-9 * std::abs(m / ixx));
      // The bending moment vector: sum x f_z = -M . y_axis.
      EXPECT_NEAR(t.moment.dot(f.y), -m, 1e-15);
    } else {
      EXPECT_NEAR(t.c2, m / iyy, 1e-9 * std::abs(m / iyy));
      EXPECT_NEAR(t.c1, 0.0, 1e-9 * std::abs(m / iyy));
      EXPECT_NEAR(t.moment.dot(f.x), m, 1e-15);
    }
    EXPECT_NEAR(t.t_x, 0.0, 1e-6);
    EXPECT_NEAR(t.t_y, 0.0, 1e-6);
  }
}

// Uniform shear tractions cannot carry a twist: the circulating forces have no resultant, so
// t_x = t_y = 0, and the traction field has no moment about the normal. Eq. 3.14f / 3.18
// keeps the twist aside as M_z, and face_load() (eq. 3.20) puts it back.
TEST(FaceTraction, PureTwistIsNotCarriedByTheShearTractions) {
  const Frame f = tilted_frame();
  const auto poly = rectangle(f, kB, kH);
  const FaceGeometry g = face_geometry(poly, f.n, f.x);
  const double r = 0.4e-3, f0 = 5.0;
  std::vector<PointForce> forces;
  for (int k = 0; k < 8; ++k) {
    const double a = k * M_PI / 4.0;
    const Vector3d radial = std::cos(a) * f.x + std::sin(a) * f.y;
    forces.push_back({f.c + r * radial, f0 * f.n.cross(radial)});
  }
  const FaceTractions t = face_tractions(g, forces);
  EXPECT_NEAR(t.t_x, 0.0, 1e-6);
  EXPECT_NEAR(t.t_y, 0.0, 1e-6);
  EXPECT_NEAR(t.t_o, 0.0, 1e-6);
  EXPECT_NEAR(t.c1, 0.0, 1e-3);
  EXPECT_NEAR(t.c2, 0.0, 1e-3);
  EXPECT_NEAR(t.m_z, 8 * r * f0, 1e-15);  // the twist, kept aside
  const FaceLoad field = integrate_tractions(g, t, poly);
  expect_vec_near(field.force, Vector3d::Zero(), 1e-12);
  expect_vec_near(field.moment, Vector3d::Zero(), 1e-15);  // not represented by the field
  const FaceLoad total = face_load(g, t);
  expect_vec_near(total.moment, 8 * r * f0 * f.n, 1e-15);
}

TEST(FaceTraction, RandomForcesReintegrateToTheirResultant) {
  const Frame f = tilted_frame();
  const auto poly = rectangle(f, kB, kH);
  const FaceGeometry g = face_geometry(poly, f.n, f.x);
  std::mt19937_64 rng(20240917);
  std::uniform_real_distribution<double> ux(-kB / 2, kB / 2), uy(-kH / 2, kH / 2);
  std::uniform_real_distribution<double> uf(-10.0, 10.0), uz(-2e-6, 2e-6);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 12);
    std::vector<PointForce> forces;
    Vector3d force = Vector3d::Zero(), moment = Vector3d::Zero();
    for (int k = 0; k < n; ++k) {
      const Vector3d arm = ux(rng) * f.x + uy(rng) * f.y;
      const Vector3d fk(uf(rng), uf(rng), uf(rng));
      // Contact points sit a little off the face (overlap); the arm is the projection.
      forces.push_back({f.c + arm + uz(rng) * f.n, fk});
      force += fk;
      moment += arm.cross(fk);
    }
    const FaceTractions t = face_tractions(g, forces);
    const FaceLoad field = integrate_tractions(g, t, poly);
    expect_vec_near(field.force, force, 1e-12);
    // Bending moments about the in-plane axes come back; the field carries no twist.
    EXPECT_NEAR(field.moment.dot(f.x), moment.dot(f.x), 1e-15);
    EXPECT_NEAR(field.moment.dot(f.y), moment.dot(f.y), 1e-15);
    EXPECT_NEAR(field.moment.dot(f.n), 0.0, 1e-15);
    EXPECT_NEAR(t.m_z, moment.dot(f.n), 1e-15);
    // Eq. 3.20 with the twist: the whole discrete load, also about another point.
    const FaceLoad total = face_load(g, t);
    expect_vec_near(total.force, force, 1e-12);
    expect_vec_near(total.moment, moment, 1e-15);
    const Vector3d p(1e-3, 2e-3, -3e-3);
    Vector3d mp = Vector3d::Zero();
    for (const auto& pf : forces) {
      const Vector3d on_plane = pf.point - (pf.point - f.c).dot(f.n) * f.n;
      mp += (on_plane - p).cross(pf.force);
    }
    expect_vec_near(moment_about(total, p), mp, 1e-14);
  }
}

// Eq. 3.15 in full: a frame origin off the centroid (Q_x, Q_y != 0) gives the same field.
TEST(FaceTraction, FrameOffTheCentroidGivesTheSameField) {
  const Frame f = tilted_frame();
  const FaceGeometry g = face_geometry(rectangle(f, kB, kH), f.n, f.x);
  const double dx = 0.3e-3, dy = -0.2e-3, a = g.area;
  FaceGeometry s = g;  // parallel axes, by hand
  s.origin = g.to_world(dx, dy);
  s.q_y = -a * dx;
  s.q_x = -a * dy;
  s.i_xx = g.i_xx + a * dx * dx;
  s.i_yy = g.i_yy + a * dy * dy;
  s.i_xy = g.i_xy + a * dx * dy;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(-kB / 2, kB / 2), uy(-kH / 2, kH / 2);
  std::uniform_real_distribution<double> uf(-10.0, 10.0);
  std::vector<PointForce> forces;
  for (int k = 0; k < 6; ++k) {
    forces.push_back({g.to_world(ux(rng), uy(rng)), Vector3d(uf(rng), uf(rng), uf(rng))});
  }
  const FaceTractions tc = face_tractions(g, forces);
  const FaceTractions ts = face_tractions(s, forces);
  ASSERT_GT(std::abs(tc.c1), 1e6);  // a real gradient
  EXPECT_NEAR(ts.t_x, tc.t_x, 1e-6);
  EXPECT_NEAR(ts.t_y, tc.t_y, 1e-6);
  for (const Vector3d& q : {g.to_world(0, 0), g.to_world(kB / 2, kH / 2), g.to_world(-kB / 2, 0)}) {
    const Eigen::Vector2d lc = g.to_local(q), ls = s.to_local(q);
    EXPECT_NEAR(ts.t_n(ls.x(), ls.y()), tc.t_n(lc.x(), lc.y()), 1e-6);
  }
  // The same total load either way (eq. 3.20).
  const FaceLoad lc = face_load(g, tc), ls = face_load(s, ts);
  expect_vec_near(ls.force, lc.force, 1e-12);
  expect_vec_near(moment_about(ls, f.c), moment_about(lc, f.c), 1e-15);
}

// --- Crack plane (eqs 3.20-3.21) ----------------------------------------------------------

namespace {

// A box body [-kL, kL] x [-kY, kY] x [-kZ, kZ] (4 x 2 x 1 mm).
const double kL = 2e-3, kY = 1e-3, kZ = 0.5e-3;

struct BodyFace {
  std::vector<Vector3d> polygon;
  Vector3d normal, x_axis;
  std::vector<PointForce> forces;
};

/// The six faces of the box, unloaded; index 0..5 = +x, -x, +y, -y, +z, -z.
std::vector<BodyFace> box() {
  std::vector<BodyFace> faces;
  const Vector3d h(kL, kY, kZ);
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {1, -1}) {
      const Vector3d n = sign * Vector3d::Unit(axis);
      const Vector3d u = Vector3d::Unit((axis + 1) % 3), v = Vector3d::Unit((axis + 2) % 3);
      const Vector3d c = sign * h(axis) * Vector3d::Unit(axis);
      const double hu = h((axis + 1) % 3), hv = h((axis + 2) % 3);
      faces.push_back(
          {{c - hu * u - hv * v, c + hu * u - hv * v, c + hu * u + hv * v, c - hu * u + hv * v},
           n,
           u,
           {}});
    }
  }
  return faces;
}

/// Grid forces of a uniform traction over box face `i`.
void load_face(std::vector<BodyFace>& faces, int i, const Vector3d& traction) {
  const int axis = i / 2;
  const Vector3d h(kL, kY, kZ);
  const Vector3d u = Vector3d::Unit((axis + 1) % 3), v = Vector3d::Unit((axis + 2) % 3);
  const Vector3d c = (i % 2 == 0 ? 1.0 : -1.0) * h(axis) * Vector3d::Unit(axis);
  faces[i].forces = grid(c, u, h((axis + 1) % 3), v, h((axis + 2) % 3), 6, 6,
                         [&](const Vector3d&) { return traction; });
}

/// Tractions of every face, then the fragment behind `plane` (whole and cut faces).
CrackPlaneLoad cut(const std::vector<BodyFace>& faces, const CrackPlane& plane,
                   const std::vector<Vector3d>& section, const Vector3d& x_axis,
                   const Vector3d& centroid, const FragmentInertia& inertia = {}) {
  std::vector<FaceLoad> loads;
  for (const auto& bf : faces) {
    const FaceGeometry g = face_geometry(bf.polygon, bf.normal, bf.x_axis);
    const FaceTractions t = face_tractions(g, bf.forces);
    loads.push_back(face_part_load(g, t, bf.polygon, plane));
  }
  return crack_plane_load(loads, centroid, section, plane, x_axis, inertia);
}

/// The box's cross-section at x = x0.
std::vector<Vector3d> section_at(double x0) {
  return {{x0, -kY, -kZ}, {x0, kY, -kZ}, {x0, kY, kZ}, {x0, -kY, kZ}};
}

}  // namespace

TEST(CrackPlane, ClipKeepsTheFragmentSide) {
  const auto poly = section_at(0.0);  // in the plane x = 0; cut it by y = 0.25 mm
  const CrackPlane plane{Vector3d(0, 0.25e-3, 0), Vector3d(0, 1, 0)};
  const auto part = clip_polygon(poly, plane);
  ASSERT_EQ(part.size(), 4u);
  const FaceGeometry g = face_geometry(part, Vector3d::UnitX(), Vector3d::UnitY());
  EXPECT_NEAR(g.area, (0.25e-3 + kY) * 2 * kZ, 1e-18);
  EXPECT_TRUE(clip_polygon(poly, CrackPlane{Vector3d(0, -2e-3, 0), Vector3d(0, 1, 0)}).empty());
  EXPECT_EQ(clip_polygon(poly, CrackPlane{Vector3d(0, 2e-3, 0), Vector3d(0, 1, 0)}).size(), 4u);
}

TEST(CrackPlane, CutFaceCarriesItsPartOfTheField) {
  // A face x in [-1, 1] mm, y in [-0.5, 0.5] mm with a random load: the part beyond x = c
  // carries the linear field over [c, 1 mm] (closed-form integrals) and the area share of
  // the twist; the whole face carries face_load().
  const Frame f = tilted_frame();
  const auto poly = rectangle(f, kB, kH);
  const FaceGeometry g = face_geometry(poly, f.n, f.x);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ux(-kB / 2, kB / 2), uy(-kH / 2, kH / 2);
  std::uniform_real_distribution<double> uf(-10.0, 10.0);
  std::vector<PointForce> forces;
  for (int k = 0; k < 7; ++k) {
    forces.push_back({g.to_world(ux(rng), uy(rng)), Vector3d(uf(rng), uf(rng), uf(rng))});
  }
  const FaceTractions t = face_tractions(g, forces);
  // Fragment behind the plane with normal -x through x = c: the part x >= c.
  const double c = 0.25e-3, x1 = kB / 2;
  const FaceLoad part = face_part_load(g, t, poly, CrackPlane{g.to_world(c, 0), -f.x});
  const double w = x1 - c, a = w * kH, xm = (x1 + c) / 2;
  const double ixx = kH * (x1 * x1 * x1 - c * c * c) / 3, iyy = w * kH * kH * kH / 12;
  const double n_int = t.t_o * a + t.c1 * a * xm;            // integral t_n dA
  const double x_int = t.t_o * a * xm + t.c1 * ixx;          // integral x t_n dA
  const double y_int = t.c2 * iyy;                           // integral y t_n dA
  const double twist = t.t_y * a * xm + t.m_z * a / g.area;  // shear's own + the share of M_z
  expect_vec_near(part.force, n_int * f.n + t.t_x * a * f.x + t.t_y * a * f.y, 1e-12);
  expect_vec_near(part.moment, y_int * f.x - x_int * f.y + twist * f.n, 1e-15);
  EXPECT_GT(std::abs(t.m_z), 1e-4);
  // Nothing beyond, everything behind.
  const FaceLoad none = face_part_load(g, t, poly, CrackPlane{g.to_world(-2e-3, 0), f.x});
  expect_vec_near(none.force, Vector3d::Zero(), 0.0);
  const FaceLoad all = face_part_load(g, t, poly, CrackPlane{g.to_world(2e-3, 0), f.x});
  const FaceLoad whole = face_load(g, t);
  expect_vec_near(all.force, whole.force, 1e-12);
  expect_vec_near(all.moment, whole.moment, 1e-15);
}

TEST(CrackPlane, TensionGivesForceOverSectionArea) {
  const double sigma = 2e6;  // Pa on the end faces
  auto faces = box();
  load_face(faces, 0, Vector3d(sigma, 0, 0));
  load_face(faces, 1, Vector3d(-sigma, 0, 0));
  const double f = sigma * 4 * kY * kZ, ac = 4 * kY * kZ;
  for (double x0 : {0.0, 0.7 * kL, -0.4 * kL}) {
    // Fragment on +x (crack normal -x) and on -x (crack normal +x).
    for (int side : {1, -1}) {
      const CrackPlane plane{Vector3d(x0, 0, 0), Vector3d(-side, 0, 0)};
      const Vector3d g((x0 + side * kL) / 2, 0, 0);
      const CrackPlaneLoad c = cut(faces, plane, section_at(x0), Vector3d::UnitY(), g);
      EXPECT_NEAR(c.section.area, ac, 1e-18);
      EXPECT_NEAR(c.tractions.t_o, f / ac, 1e-6);  // F / A_c, tension
      EXPECT_NEAR(c.tractions.t_o, sigma, 1e-6);
      EXPECT_NEAR(c.tractions.t_s(), 0.0, 1e-6);
      EXPECT_NEAR(c.tractions.c1, 0.0, 1e-3);
      EXPECT_NEAR(c.tractions.c2, 0.0, 1e-3);
      expect_vec_near(c.force, Vector3d(side * -f, 0, 0), 1e-12);
      expect_vec_near(c.moment, Vector3d::Zero(), 1e-15);
      const BeamStresses b = beam_stresses(c);
      EXPECT_NEAR(b.sigma, f / ac, 1e-6);
      EXPECT_NEAR(b.tau, 0.0, 1e-6);
      // The moment is moved to the section centroid, so a fragment centroid given off the
      // axis (where the applied force has an arm) changes nothing in static equilibrium.
      const CrackPlaneLoad odd =
          cut(faces, plane, section_at(x0), Vector3d::UnitY(), Vector3d(5e-3, 1e-3, 2e-3));
      EXPECT_GT(odd.applied_moment.norm(), 1e-3);
      expect_vec_near(odd.moment, Vector3d::Zero(), 1e-15);
      EXPECT_NEAR(odd.tractions.t_o, sigma, 1e-6);
    }
  }
}

TEST(CrackPlane, ObliqueCutResolvesTheStress) {
  const double sigma = 2e6, phi = 0.4;
  auto faces = box();
  load_face(faces, 0, Vector3d(sigma, 0, 0));
  load_face(faces, 1, Vector3d(-sigma, 0, 0));
  const double t = std::tan(phi);
  const CrackPlane plane{Vector3d::Zero(), -Vector3d(std::cos(phi), std::sin(phi), 0)};
  const std::vector<Vector3d> section = {
      {-kY * t, kY, -kZ}, {-kY * t, kY, kZ}, {kY * t, -kY, kZ}, {kY * t, -kY, -kZ}};
  const CrackPlaneLoad c = cut(faces, plane, section, Vector3d::UnitZ(), Vector3d(kL / 2, 0, 0));
  EXPECT_NEAR(c.section.area, 4 * kY * kZ / std::cos(phi), 1e-18);
  const double co = std::cos(phi), si = std::sin(phi);
  EXPECT_NEAR(c.tractions.t_o, sigma * co * co, 1e-6);    // sigma cos^2 phi
  EXPECT_NEAR(c.tractions.t_s(), sigma * si * co, 1e-6);  // sigma sin phi cos phi
  EXPECT_NEAR(c.tractions.t_x, 0.0, 1e-6);                // x along z: no shear that way
  EXPECT_NEAR(c.tractions.c1, 0.0, 1e-3);
  EXPECT_NEAR(c.tractions.c2, 0.0, 1e-3);
  // Jourawski on the rectangular section, shear along its long side: 3/2 of the mean.
  const BeamStresses b = beam_stresses(c);
  EXPECT_NEAR(b.tau, 1.5 * sigma * si * co, 1e-6);
  EXPECT_NEAR(b.sigma, sigma * co * co, 1e-6);
}

TEST(CrackPlane, PureShearGivesTheShearStress) {
  // tau_xy = tau0: x faces carry +-tau0 along y, y faces +-tau0 along x (a balanced couple
  // pair); the y faces are cut by the crack.
  const double tau0 = 1.5e6;
  auto faces = box();
  load_face(faces, 0, Vector3d(0, tau0, 0));
  load_face(faces, 1, Vector3d(0, -tau0, 0));
  load_face(faces, 2, Vector3d(tau0, 0, 0));
  load_face(faces, 3, Vector3d(-tau0, 0, 0));
  for (double x0 : {0.0, 0.5 * kL}) {
    const CrackPlane plane{Vector3d(x0, 0, 0), -Vector3d::UnitX()};
    const CrackPlaneLoad c =
        cut(faces, plane, section_at(x0), Vector3d::UnitY(), Vector3d((x0 + kL) / 2, 0, 0));
    // The traction on the fragment's face (normal -x) is sigma . n = -tau0 along y.
    EXPECT_NEAR(c.tractions.t_x, -tau0, 1e-6);
    EXPECT_NEAR(c.tractions.t_y, 0.0, 1e-6);
    EXPECT_NEAR(c.tractions.t_s(), tau0, 1e-6);
    EXPECT_NEAR(c.tractions.t_o, 0.0, 1e-6);
    EXPECT_NEAR(c.tractions.c1, 0.0, 1e-3);
    EXPECT_NEAR(c.tractions.c2, 0.0, 1e-3);
    expect_vec_near(c.moment, Vector3d::Zero(), 1e-15);
    // Eq. 3.24 with V = tau0 A_c on a 2 mm (along the shear) x 1 mm section: 1.5 tau0.
    const BeamStresses b = beam_stresses(c);
    EXPECT_NEAR(b.shear_force, tau0 * 4 * kY * kZ, 1e-9);
    EXPECT_NEAR(b.chord, 2 * kZ, 1e-15);
    EXPECT_NEAR(b.q, 2 * kZ * kY * kY / 2, 1e-18);
    EXPECT_NEAR(b.inertia, 2 * kZ * 8 * kY * kY * kY / 12, 1e-24);
    EXPECT_NEAR(b.tau, 1.5 * tau0, 1e-6);
  }
}

TEST(CrackPlane, PureBendingGivesMcOverI) {
  // End couples: +-P at y = +-e on x = +kL, mirrored on x = -kL (a bar in pure bending).
  const double p = 4.0, e = 0.6e-3;
  auto faces = box();
  faces[0].forces = {{Vector3d(kL, e, 0), Vector3d(p, 0, 0)},
                     {Vector3d(kL, -e, 0), Vector3d(-p, 0, 0)}};
  faces[1].forces = {{Vector3d(-kL, e, 0), Vector3d(-p, 0, 0)},
                     {Vector3d(-kL, -e, 0), Vector3d(p, 0, 0)}};
  const double m = 2 * e * p;                       // bending moment
  const double i = 2 * kZ * 8 * kY * kY * kY / 12;  // about z, section 2 mm (y) x 1 mm (z)
  const CrackPlane plane{Vector3d(0.3e-3, 0, 0), -Vector3d::UnitX()};
  // Section x axis along world y, so C1 is the gradient along y: sigma_xx = (M / I) y.
  const CrackPlaneLoad c =
      cut(faces, plane, section_at(0.3e-3), Vector3d::UnitY(), Vector3d(1.15e-3, 0, 0));
  EXPECT_NEAR(c.tractions.t_o, 0.0, 1e-6);
  EXPECT_NEAR(c.tractions.c1, m / i, 1e-9 * m / i);
  EXPECT_NEAR(c.tractions.c2, 0.0, 1e-9 * m / i);
  EXPECT_NEAR(c.tractions.t_s(), 0.0, 1e-6);
  const BeamStresses b = beam_stresses(c);
  EXPECT_NEAR(b.sigma, m * kY / i, 1e-9 * m * kY / i);  // M c / I at the tensile fibre
}

TEST(CrackPlane, HexagonalPrismUnderAxialTension) {
  // A prism of side s along z, pulled by F through six equal forces at the corners of each
  // basal face, cut parallel to the basal plane: t_n = F / A_hex on the hexagonal section.
  const double s = 0.5e-3, hz = 1e-3, f = 3.0;
  const Frame top{Vector3d(0, 0, hz), Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()};
  const Frame bottom{Vector3d(0, 0, -hz), Vector3d::UnitX(), -Vector3d::UnitY(),
                     -Vector3d::UnitZ()};
  std::vector<BodyFace> faces;
  faces.push_back({hexagon(top, s), top.n, top.x, {}});
  faces.push_back({hexagon(bottom, s), bottom.n, bottom.x, {}});
  for (const Vector3d& v : faces[0].polygon) faces[0].forces.push_back({v, f / 6 * top.n});
  for (const Vector3d& v : faces[1].polygon) faces[1].forces.push_back({v, f / 6 * bottom.n});
  const auto hex0 = hexagon(top, s);
  for (int k = 0; k < 6; ++k) {
    const Vector3d a = hex0[k] - Vector3d(0, 0, hz), b = hex0[(k + 1) % 6] - Vector3d(0, 0, hz);
    const Vector3d n = (0.5 * (a + b)).normalized();
    faces.push_back({{a - Vector3d(0, 0, hz), b - Vector3d(0, 0, hz), b + Vector3d(0, 0, hz),
                      a + Vector3d(0, 0, hz)},
                     n,
                     b - a,
                     {}});
  }
  const double z0 = 0.3e-3;
  const CrackPlane plane{Vector3d(0, 0, z0), -Vector3d::UnitZ()};
  const CrackPlaneLoad c =
      cut(faces, plane, hexagon(Frame{Vector3d(0, 0, z0), top.x, top.y, top.n}, s),
          Vector3d::UnitX(), Vector3d(0, 0, (z0 + hz) / 2));
  const double area = 1.5 * std::sqrt(3.0) * s * s;
  EXPECT_NEAR(c.section.area, area, 1e-18);
  EXPECT_NEAR(c.tractions.t_o, f / area, 1e-6);
  EXPECT_NEAR(c.tractions.c1, 0.0, 1e-3);
  EXPECT_NEAR(c.tractions.c2, 0.0, 1e-3);
  EXPECT_NEAR(c.tractions.t_s(), 0.0, 1e-6);
}

TEST(CrackPlane, InertiaOfAnAcceleratingBodyLoadsTheSection) {
  // Only the +x end is pulled: the body accelerates with a = F / m, and each half needs
  // m a / 2 = F / 2 through the section (d'Alembert), a tension of F / (2 A_c).
  const double sigma = 2e6;
  auto faces = box();
  load_face(faces, 0, Vector3d(sigma, 0, 0));
  const double f = sigma * 4 * kY * kZ, ac = 4 * kY * kZ;
  const FragmentInertia half{Vector3d(f / 2, 0, 0), Vector3d::Zero()};
  const CrackPlaneLoad near = cut(faces, CrackPlane{Vector3d::Zero(), -Vector3d::UnitX()},
                                  section_at(0), Vector3d::UnitY(), Vector3d(kL / 2, 0, 0), half);
  const CrackPlaneLoad far = cut(faces, CrackPlane{Vector3d::Zero(), Vector3d::UnitX()},
                                 section_at(0), Vector3d::UnitY(), Vector3d(-kL / 2, 0, 0), half);
  EXPECT_NEAR(near.tractions.t_o, f / (2 * ac), 1e-6);
  EXPECT_NEAR(far.tractions.t_o, f / (2 * ac), 1e-6);
  expect_vec_near(near.force, -far.force, 1e-12);
  // Without the d'Alembert term the far half would see nothing.
  const CrackPlaneLoad quasi = cut(faces, CrackPlane{Vector3d::Zero(), Vector3d::UnitX()},
                                   section_at(0), Vector3d::UnitY(), Vector3d(-kL / 2, 0, 0));
  EXPECT_NEAR(quasi.tractions.t_o, 0.0, 1e-6);
}

// --- Eq. 3.24 on a hexagonal section ------------------------------------------------------

TEST(BeamStresses, JourawskiOnARegularHexagon) {
  // Closed forms for a regular hexagon of side s, V = t_s A: shear across the flats (chord =
  // long diagonal 2 s, Q = s^3 / 2) gives tau = 1.2 t_s; shear along a diagonal (chord =
  // sqrt(3) s, Q = 7 sqrt(3) s^3 / 24) gives tau = 1.4 t_s. I = 5 sqrt(3) s^4 / 16 both ways.
  const Frame f = tilted_frame();
  const double s = 0.6e-3;
  const auto poly = hexagon(f, s);  // vertices along +-x, flats across y
  const FaceGeometry g = face_geometry(poly, f.n, f.x);
  FaceTractions across;
  across.t_y = 1e6;  // across the flats
  BeamStresses b = beam_stresses(g, poly, across);
  EXPECT_NEAR(b.chord, 2 * s, 1e-15);
  EXPECT_NEAR(b.q, s * s * s / 2, 1e-22);
  EXPECT_NEAR(b.inertia, 5 * std::sqrt(3.0) / 16 * s * s * s * s, 1e-27);
  EXPECT_NEAR(b.tau, 1.2e6, 1e-3);
  FaceTractions along;
  along.t_x = -1e6;  // towards a vertex
  b = beam_stresses(g, poly, along);
  EXPECT_NEAR(b.chord, std::sqrt(3.0) * s, 1e-15);
  EXPECT_NEAR(b.q, 7 * std::sqrt(3.0) / 24 * s * s * s, 1e-22);
  EXPECT_NEAR(b.tau, 1.4e6, 1e-3);
  // Bending about y on the hexagon: the tensile fibre is the vertex at x = s.
  FaceTractions bend;
  bend.t_o = 1e5;
  bend.c1 = 2e9;
  b = beam_stresses(g, poly, bend);
  EXPECT_NEAR(b.sigma, 1e5 + 2e9 * s, 1e-6);
}

TEST(BeamStresses, JourawskiOnAnUnsymmetricTrapezoid) {
  // Right trapezoid (0,0), (2L,0), (L,L), (0,L): centroid (7/9, 4/9) L. Shear along x: the
  // chord is the vertical through the centroid (length L, not symmetric about it), Q of the
  // part beyond it = 49/162 L^3, I = 37/108 L^4, so tau = V Q / (I b) = 147/111 t_s.
  const Frame f = tilted_frame();
  const double l = 1e-3;
  const std::vector<Vector3d> poly = {f.c, f.c + 2 * l * f.x, f.c + l * f.x + l * f.y,
                                      f.c + l * f.y};
  const FaceGeometry g = face_geometry(poly, f.n, f.x);
  expect_vec_near(g.origin, f.c + 7.0 / 9 * l * f.x + 4.0 / 9 * l * f.y, 1e-15);
  FaceTractions t;
  t.t_x = 1e6;
  const BeamStresses b = beam_stresses(g, poly, t);
  EXPECT_NEAR(b.chord, l, 1e-15);
  EXPECT_NEAR(b.q, 49.0 / 162 * l * l * l, 1e-22);
  EXPECT_NEAR(b.inertia, 37.0 / 108 * l * l * l * l, 1e-25);
  EXPECT_NEAR(b.tau, 147.0 / 111 * 1e6, 1e-3);
}

// --- Fracture criterion (eqs 3.22-3.25) ---------------------------------------------------

namespace {

FractureParams params() {
  FractureParams p;
  p.sigma_f_hyd = 10e6;  // 10 MPa mean tension opens the gate
  p.k_ic = 3e6;          // 3 MPa sqrt(m)
  p.crack_length = 10e-6;
  return p;
}

const Eigen::Matrix3d kOpen = Eigen::Vector3d(30e6, 5e6, 10e6).asDiagonal();  // mean 15 MPa

}  // namespace

TEST(FractureCriterion, BelowTheHydrostaticGateNeverFails) {
  const FractureParams p = params();
  const double sigma_c = p.k_ic / std::sqrt(M_PI * p.crack_length);
  Eigen::Matrix3d below = Eigen::Vector3d(20e6, 5e6, 4.99e6).asDiagonal();  // mean 9.997 MPa
  below(0, 1) = below(1, 0) = 50e6;  // shear does not enter the gate
  const FractureResult r = fracture_check(p, below, 100 * sigma_c, 100 * sigma_c);
  EXPECT_FALSE(r.gate);
  EXPECT_GT(r.criterion, 1.0);
  EXPECT_FALSE(r.fails);
  EXPECT_NEAR(r.mean_stress, (20e6 + 5e6 + 4.99e6) / 3, 1e-6);
  // Compression is negative: a compressed grain stays shut.
  const FractureResult c =
      fracture_check(p, -1e8 * Eigen::Matrix3d::Identity(), 100 * sigma_c, 0.0);
  EXPECT_FALSE(c.gate);
  EXPECT_FALSE(c.fails);
  // Exactly at the threshold the gate is open (>=).
  const FractureResult at = fracture_check(p, 10e6 * Eigen::Matrix3d::Identity(), 0.0, 0.0);
  EXPECT_TRUE(at.gate);
  EXPECT_FALSE(at.fails);
}

TEST(FractureCriterion, PureModeIFailsAtKIcOverRootPiA) {
  const FractureParams p = params();
  const double sigma_c = p.k_ic / std::sqrt(M_PI * p.crack_length);  // eq. 3.23 with K_I = K_Ic
  const FractureResult below = fracture_check(p, kOpen, sigma_c * (1 - 1e-9), 0.0);
  const FractureResult above = fracture_check(p, kOpen, sigma_c * (1 + 1e-9), 0.0);
  EXPECT_TRUE(below.gate);
  EXPECT_FALSE(below.fails);
  EXPECT_TRUE(above.fails);
  EXPECT_NEAR(above.k_i, p.k_ic, 1e-6 * p.k_ic);
  EXPECT_EQ(above.k_ii, 0.0);
  // A compressive normal stress, however large, does not open the crack.
  const FractureResult shut = fracture_check(p, kOpen, -10 * sigma_c, 0.0);
  EXPECT_LT(shut.k_i, 0.0);
  EXPECT_EQ(shut.criterion, 0.0);
  EXPECT_FALSE(shut.fails);
}

TEST(FractureCriterion, PureModeIIFailsAtCKIc) {
  const FractureParams p = params();
  EXPECT_DOUBLE_EQ(p.c, 0.816);
  const double tau_c = p.c * p.k_ic / std::sqrt(M_PI * p.crack_length);
  EXPECT_FALSE(fracture_check(p, kOpen, 0.0, tau_c * (1 - 1e-9)).fails);
  EXPECT_TRUE(fracture_check(p, kOpen, 0.0, tau_c * (1 + 1e-9)).fails);
  EXPECT_TRUE(fracture_check(p, kOpen, 0.0, -tau_c * (1 + 1e-9)).fails);  // either sense
  // Pure mode I at the mode II threshold is still safe (C < 1).
  EXPECT_FALSE(fracture_check(p, kOpen, tau_c, 0.0).fails);
  // Shear alone still cleaves a crack pressed shut.
  EXPECT_TRUE(fracture_check(p, kOpen, -5 * tau_c, tau_c * (1 + 1e-9)).fails);
}

TEST(FractureCriterion, MixedModeOnTheEllipse) {
  const FractureParams p = params();
  const double root = std::sqrt(M_PI * p.crack_length);
  const double sigma_c = p.k_ic / root, tau_c = p.c * p.k_ic / root;
  for (double th : {0.2, 0.7, 1.3}) {
    const double sg = sigma_c * std::cos(th), ta = tau_c * std::sin(th);
    EXPECT_NEAR(fracture_check(p, kOpen, sg, ta).criterion, 1.0, 1e-12);
    EXPECT_FALSE(fracture_check(p, kOpen, sg * (1 - 1e-9), ta * (1 - 1e-9)).fails);
    EXPECT_TRUE(fracture_check(p, kOpen, sg * (1 + 1e-9), ta * (1 + 1e-9)).fails);
  }
  // Half way in each mode: 1/4 + 1/4.
  EXPECT_NEAR(fracture_check(p, kOpen, sigma_c / 2, tau_c / 2).criterion, 0.5, 1e-12);
}

TEST(FractureCriterion, CrackPlaneStressesFeedTheCriterion) {
  // End to end: end tension on the box, cut in the middle; the section fails exactly when
  // the applied stress reaches K_Ic / sqrt(pi a).
  const FractureParams p = params();
  const double sigma_c = p.k_ic / std::sqrt(M_PI * p.crack_length);
  for (double scale : {1 - 1e-6, 1 + 1e-6}) {
    auto faces = box();
    load_face(faces, 0, Vector3d(scale * sigma_c, 0, 0));
    load_face(faces, 1, Vector3d(-scale * sigma_c, 0, 0));
    const CrackPlaneLoad c = cut(faces, CrackPlane{Vector3d::Zero(), -Vector3d::UnitX()},
                                 section_at(0), Vector3d::UnitY(), Vector3d(kL / 2, 0, 0));
    const FractureResult r = fracture_check(p, kOpen, beam_stresses(c));
    EXPECT_EQ(r.fails, scale > 1) << "scale " << scale;
  }
}

// The check's gate (eq. 3.22) reads each body's mean stress from the diagonal of its sum
// alone; assess decides from the whole matrix of eq. 2.17. They must agree to the bit, or
// the gate could turn away a body exactly at the threshold that assess would take.
TEST(HydrostaticGate, MeanFromTheDiagonalIsTheTraceOfTheWholeStressToTheBit) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-12.0, 3.0);
  int differ_from_plain_sum = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    Eigen::Matrix3d sum;
    for (int i = 0; i < 9; ++i) sum(i) = u(rng) * std::pow(10.0, e(rng));
    const double volume = std::pow(10.0, e(rng) - 6.0) * (1.0 + std::abs(u(rng)));
    const Eigen::Matrix3d sigma = (sum + sum.transpose()) / (2.0 * volume);  // as the check's stress_from
    const double want = sigma.trace() / 3.0;
    const double got = mean_stress_from_diagonal(sum.diagonal(), volume);
    ASSERT_EQ(std::memcmp(&got, &want, sizeof(double)), 0) << trial << ": " << got << " vs " << want;
    const Eigen::Vector3d d = sigma.diagonal();
    differ_from_plain_sum += ((d.x() + d.y()) + d.z()) / 3.0 != want;
  }
  // The order of the sum matters: summed left to right, a few hundred differ (so this test
  // tells the orders apart).
  EXPECT_GT(differ_from_plain_sum, 100);
}

// --- A fragment's mass properties and d'Alembert terms --------------------------------------

namespace {

/// A regular hexagonal prism (side s, thickness t) centred on f.c with its axis along f.n:
/// faces with their outward normals.
struct Prism {
  std::vector<std::vector<Vector3d>> faces;
  std::vector<Vector3d> normals;
};

Prism hex_prism(const Frame& f, double s, double t) {
  Prism p;
  const Frame top{f.c + t / 2 * f.n, f.x, f.y, f.n}, bottom{f.c - t / 2 * f.n, f.x, f.y, f.n};
  const auto up = hexagon(top, s), down = hexagon(bottom, s);
  p.faces.push_back(up);
  p.normals.push_back(f.n);
  p.faces.push_back({down.rbegin(), down.rend()});
  p.normals.push_back(-f.n);
  for (int k = 0; k < 6; ++k) {
    const int j = (k + 1) % 6;
    p.faces.push_back({down[k], down[j], up[j], up[k]});
    const Vector3d mid = (down[k] + down[j]) / 2 - bottom.c;
    p.normals.push_back(mid.normalized());
  }
  return p;
}

}  // namespace

TEST(FragmentMass, HalfAHexagonalPrismHasTheClosedFormVolumeCentroidAndInertia) {
  // Cut through two opposite corners, half the prism is a trapezoidal prism: volume
  // 3 sqrt(3) / 4 s^2 t, centroid 2 sqrt(3) s / 9 from the axis. Uncut, the prism's own
  // closed forms: J_axis = 5 sqrt(3) / 8 s^4 t, J_across = 5 sqrt(3) / 16 s^4 t + V t^2 / 12.
  const Frame f = tilted_frame();
  const double s = 0.5e-3, t = 0.8e-3;
  const Prism p = hex_prism(f, s, t);
  const CrackPlane far{f.c + 10 * s * f.x, f.x};  // misses the prism
  const SolidMass whole = fragment_mass(p.faces, p.normals, {}, far);
  const double v = 1.5 * std::sqrt(3.0) * s * s * t;
  EXPECT_NEAR(whole.volume, v, 1e-12 * v);
  expect_vec_near(whole.centroid, f.c, 1e-15);
  const Eigen::Matrix3d r = (Eigen::Matrix3d() << f.x, f.y, f.n).finished();
  const Eigen::Matrix3d local = r.transpose() * whole.inertia * r;
  const double j_axis = 5 * std::sqrt(3.0) / 8 * std::pow(s, 4) * t;
  const double j_across = 5 * std::sqrt(3.0) / 16 * std::pow(s, 4) * t + v * t * t / 12;
  EXPECT_NEAR(local(2, 2), j_axis, 1e-10 * j_axis);
  EXPECT_NEAR(local(0, 0), j_across, 1e-10 * j_across);
  EXPECT_NEAR(local(1, 1), j_across, 1e-10 * j_across);
  EXPECT_NEAR(local(0, 1), 0.0, 1e-10 * j_axis);
  // The half on the -y side of the plane through the corners at +-s f.x.
  const CrackPlane cut{f.c, f.y};
  const std::vector<Vector3d> section = {f.c - s * f.x - t / 2 * f.n, f.c + s * f.x - t / 2 * f.n,
                                         f.c + s * f.x + t / 2 * f.n, f.c - s * f.x + t / 2 * f.n};
  const SolidMass half = fragment_mass(p.faces, p.normals, section, cut);
  EXPECT_NEAR(half.volume, v / 2, 1e-12 * v);
  expect_vec_near(half.centroid, f.c - 2 * std::sqrt(3.0) * s / 9 * f.y, 1e-15);
}

TEST(FragmentInertia, TheTwoSidesOfAPlaneSumToTheWholeBodysForceAndAngularMomentumRate) {
  // Newton's third law through the section: whatever the motion, the two fragments' m (a - g)
  // sum to the body's, and their dH/dt about their centroids plus the moments of their m a
  // sum to the body's I alpha + omega x I omega about G.
  const Frame f = tilted_frame();
  const double s = 0.5e-3, t = 0.8e-3, rho = 3100.0;
  const Prism p = hex_prism(f, s, t);
  const SolidMass whole =
      fragment_mass(p.faces, p.normals, {}, CrackPlane{f.c + 10 * s * f.x, f.x});
  RigidMotion m;
  m.centroid = f.c;
  m.acceleration = Vector3d(3.0, -2.0, 7.0);
  m.omega = Vector3d(300.0, -500.0, 800.0);
  m.alpha = Vector3d(4e5, 1e5, -2e5);
  m.gravity = Vector3d(0.0, 0.0, -9.81);
  const Vector3d n = (0.3 * f.x + f.y + 0.2 * f.n).normalized();
  const Vector3d point = f.c + 0.2 * s * f.x;
  // The section by brute force: clip every face and collect the points on the plane.
  std::vector<Vector3d> on_plane;
  for (const auto& face : p.faces) {
    for (const auto& q : clip_polygon(face, CrackPlane{point, n})) {
      if (std::abs((q - point).dot(n)) < 1e-15) on_plane.push_back(q);
    }
  }
  Vector3d c = Vector3d::Zero();
  for (const auto& q : on_plane) c += q / on_plane.size();
  const Vector3d u = (on_plane.front() - c).normalized(), w = n.cross(u);
  std::sort(on_plane.begin(), on_plane.end(), [&](const Vector3d& a, const Vector3d& b) {
    return std::atan2((a - c).dot(w), (a - c).dot(u)) < std::atan2((b - c).dot(w), (b - c).dot(u));
  });
  on_plane.erase(
      std::unique(on_plane.begin(), on_plane.end(),
                  [](const Vector3d& a, const Vector3d& b) { return (a - b).norm() < 1e-15; }),
      on_plane.end());
  const std::vector<Vector3d> reversed(on_plane.rbegin(), on_plane.rend());
  const SolidMass one = fragment_mass(p.faces, p.normals, on_plane, CrackPlane{point, n});
  const SolidMass two = fragment_mass(p.faces, p.normals, reversed, CrackPlane{point, -n});
  EXPECT_NEAR(one.volume + two.volume, whole.volume, 1e-12 * whole.volume);
  const FragmentInertia a = fragment_inertia(m, rho, one), b = fragment_inertia(m, rho, two);
  const double mass = rho * whole.volume;
  const Vector3d force = mass * (m.acceleration - m.gravity);
  expect_vec_near(a.force + b.force, force, 1e-12 * force.norm());
  const Eigen::Matrix3d j = rho * whole.inertia;
  const Vector3d rate = j * m.alpha + m.omega.cross(j * m.omega);
  const Vector3d sum = a.moment + (one.centroid - f.c).cross(a.force) + b.moment +
                       (two.centroid - f.c).cross(b.force);
  expect_vec_near(sum, rate, 1e-9 * rate.norm());
}

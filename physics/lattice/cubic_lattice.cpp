#include "physics/lattice/cubic_lattice.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "physics/bonds/vec3.hpp"
#include "physics/simd.hpp"

namespace cleave::physics {

namespace {

constexpr int kParallelMin = 2048;

void hash_bytes(std::uint64_t& h, const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < n; ++k) {
    h ^= p[k];
    h *= 1099511628211ULL;
  }
}

}  // namespace

/// Eq. 3 (Yu's cubic cell): k_n1 = k_n2 = 2 E r / (5 (1 - 2 nu)),
/// k_s1 = k_s2 = 2 E r (1 - 4 nu) / (5 (1 - 2 nu)(1 + nu)); the effective areas of the text
/// after eq. 10: pi r^2 / 4 for first and 2 pi r^2 / 9 for second neighbours.
LatticeSprings lattice_springs(double E, double nu, double r) {
  LatticeSprings s;
  s.kn1 = s.kn2 = 2.0 * E * r / (5.0 * (1.0 - 2.0 * nu));
  s.ks1 = s.ks2 = 2.0 * E * r * (1.0 - 4.0 * nu) / (5.0 * (1.0 - 2.0 * nu) * (1.0 + nu));
  s.area1 = M_PI * r * r / 4.0;
  s.area2 = 2.0 * M_PI * r * r / 9.0;
  return s;
}

LatticeSprings tiled_areas(LatticeSprings s, double r) {
  const double scale = 4.0 * r * r / (s.area1 + 4.0 * s.area2);
  s.area1 *= scale;
  s.area2 *= scale;
  return s;
}

SurfaceCompensation surface_compensation(const LatticeSprings& s, double nu) {
  const double b = nu / (1.0 - nu);
  SurfaceCompensation c;
  c.kn_edge = 0.5 * (s.kn2 + s.ks2);
  c.kn_diagonal = 0.5 * (s.kn1 * b * b + 2.0 * b * (b - 1.0) * s.kn2 + 2.0 * b * (b + 1.0) * s.ks2);
  c.ks_edge = s.ks2 - 2.0 * c.kn_diagonal;
  c.ks_diagonal = 0.0;
  return c;
}

CubicLattice::CubicLattice(const CubicLatticeDef& def)
    : def_(def), nx_(def.nx), ny_(def.ny), nz_(def.nz) {
  const LatticeMaterial& mat = def.material;
  if (nx_ < 1 || ny_ < 1 || nz_ < 1) throw std::invalid_argument("lattice: empty grid");
  if (!(def.radius > 0)) throw std::invalid_argument("lattice: radius must be > 0");
  if (!(mat.young > 0) || !(mat.density > 0))
    throw std::invalid_argument("lattice: Young's modulus and density must be > 0");
  if (!(mat.poisson >= 0.0 && mat.poisson < 0.25))
    throw std::invalid_argument("lattice: Poisson's ratio must lie in [0, 0.25) (eq. 3)");
  const double r = def.radius;
  springs_ = lattice_springs(mat.young, mat.poisson, r);
  if (def.tiled_areas) springs_ = tiled_areas(springs_, r);
  cohesive1_ = {springs_.kn1, springs_.ks1, springs_.area1, mat.sigma_c, mat.g_c, mat.initiation};
  cohesive2_ = {springs_.kn2, springs_.ks2, springs_.area2, mat.sigma_c, mat.g_c, mat.initiation};
  const bool weak = def.weak_layer > 0 && def.weak_layer < nz_;
  if (weak) {
    if (!(mat.sigma_c > 0) || !(mat.g_c > 0))
      throw std::invalid_argument("lattice: a weak plane needs sigma_c > 0 and G_c > 0");
    limits1_ = cohesive_limits(cohesive1_);
    limits2_ = cohesive_limits(cohesive2_);
  }
  hertz_ = hertz_mindlin_params(mat.young, mat.poisson, r, mat.young, mat.poisson, r, mat.kappa,
                                mat.friction);
  mass_ = mat.density * 8.0 * r * r * r;
  inertia_ = mass_ * 4.0 * r * r / 6.0;

  const int n = nx_ * ny_ * nz_;
  x0_.resize(n);
  for (int iz = 0; iz < nz_; ++iz)
    for (int iy = 0; iy < ny_; ++iy)
      for (int ix = 0; ix < nx_; ++ix)
        x0_[index(ix, iy, iz)] =
            Eigen::Vector3d((2 * ix + 1) * r, (2 * iy + 1) * r, (2 * iz + 1) * r);
  x_ = x0_;
  v_.assign(n, Eigen::Vector3d::Zero());
  w_.assign(n, Eigen::Vector3d::Zero());
  f_.assign(n, Eigen::Vector3d::Zero());
  m_.assign(n, Eigen::Vector3d::Zero());
  q_.assign(n, Eigen::Quaterniond::Identity());
  prescribed_.assign(n, 0);

  const SurfaceCompensation comp = surface_compensation(springs_, mat.poisson);
  // Links to the 6 first and 12 second neighbours, each once (i < j).
  for (int iz = 0; iz < nz_; ++iz)
    for (int iy = 0; iy < ny_; ++iy)
      for (int ix = 0; ix < nx_; ++ix)
        for (int dz = -1; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int order = std::abs(dx) + std::abs(dy) + std::abs(dz);
              if (order == 0 || order == 3) continue;  // self, third neighbours (k = 0)
              const int jx = ix + dx, jy = iy + dy, jz = iz + dz;
              if (jx < 0 || jy < 0 || jz < 0 || jx >= nx_ || jy >= ny_ || jz >= nz_) continue;
              const int i = index(ix, iy, iz), j = index(jx, jy, jz);
              if (j <= i) continue;
              LatticeLink l;
              l.i = i;
              l.j = j;
              l.kind = static_cast<std::uint8_t>(order);
              l.rest = (x0_[j] - x0_[i]).norm();
              l.kn = order == 1 ? springs_.kn1 : springs_.kn2;
              l.ks = order == 1 ? springs_.ks1 : springs_.ks2;
              // A link lying in an outer face (both ends in its layer) is compensated.
              const int ci[3] = {ix, iy, iz}, cj[3] = {jx, jy, jz}, n3[3] = {nx_, ny_, nz_};
              for (int a = 0; a < 3; ++a) {
                if (ci[a] != cj[a]) continue;
                const int faces = (ci[a] == 0 ? 1 : 0) + (ci[a] == n3[a] - 1 ? 1 : 0);
                l.kn += faces * (order == 1 ? comp.kn_edge : comp.kn_diagonal);
                l.ks += faces * (order == 1 ? comp.ks_edge : comp.ks_diagonal);
              }
              // A link lying in a face of the weak plane is compensated as the plane opens.
              if (weak && iz == jz && (iz == def.weak_layer - 1 || iz == def.weak_layer)) {
                l.face_kn = order == 1 ? comp.kn_edge : comp.kn_diagonal;
                l.face_ks = order == 1 ? comp.ks_edge : comp.ks_diagonal;
              }
              l.breakable = weak && std::min(iz, jz) == def.weak_layer - 1 &&
                            std::max(iz, jz) == def.weak_layer &&
                            0.5 * (x0_[i].x() + x0_[j].x()) <= def.weak_end_x + 1e-6 * r;
              if (order == 1 && !l.breakable)
                l.kb = def.link_bending * mat.young * 8.0 * r * r * r / 12.0;
              if (l.breakable && 0.5 * (x0_[i].x() + x0_[j].x()) < def.notch_x - 1e-6 * r)
                l.state.phase = LinkPhase::contact;
              links_.push_back(l);
            }
  // Colours (see the header): direction of j from i, then the parity of i's cell along the
  // first axis the direction moves on. Stable, so each colour keeps the grid's order.
  {
    const auto colour = [&](const LatticeLink& l) {
      const int ix = l.i % nx_, iy = (l.i / nx_) % ny_, iz = l.i / (nx_ * ny_);
      const int d[3] = {l.j % nx_ - ix, (l.j / nx_) % ny_ - iy, l.j / (nx_ * ny_) - iz};
      static constexpr int kDirections[9][3] = {{1, 0, 0},  {0, 1, 0},  {0, 0, 1},
                                                {1, 1, 0},  {-1, 1, 0}, {1, 0, 1},
                                                {-1, 0, 1}, {0, 1, 1},  {0, -1, 1}};
      for (int c = 0; c < 9; ++c)
        if (d[0] == kDirections[c][0] && d[1] == kDirections[c][1] && d[2] == kDirections[c][2]) {
          const int axis = d[0] != 0 ? 0 : (d[1] != 0 ? 1 : 2);
          const int cell[3] = {ix, iy, iz};
          return 2 * c + (cell[axis] & 1);
        }
      throw std::logic_error("lattice: a link joins no first or second neighbour");
    };
    // Sorted by colour, and within a colour the connective links before the breakable ones
    // (the lanes take the first four at a time); stable, so each part keeps the grid's order.
    std::vector<int> keys(links_.size());
    for (std::size_t k = 0; k < links_.size(); ++k)
      keys[k] = 2 * colour(links_[k]) + (links_[k].breakable ? 1 : 0);
    std::vector<int> order(links_.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return keys[a] < keys[b]; });
    std::vector<LatticeLink> sorted(links_.size());
    std::vector<int> counts(37, 0);
    for (std::size_t k = 0; k < order.size(); ++k) {
      sorted[k] = links_[order[k]];
      ++counts[keys[order[k]] + 1];
    }
    for (int key = 0; key < 36; ++key) counts[key + 1] += counts[key];
    colour_start_.assign(19, 0);
    breakable_start_.assign(18, 0);
    for (int c = 0; c < 18; ++c) {
      colour_start_[c + 1] = counts[2 * c + 2];
      breakable_start_[c] = counts[2 * c + 1];
    }
    links_ = std::move(sorted);
  }
  // Hot data: the classes of link, and each link's ends and class.
  ends_.resize(links_.size());
  for (std::size_t k = 0; k < links_.size(); ++k) {
    const LatticeLink& l = links_[k];
    LinkClass c;
    c.rest = l.rest;
    c.kn = l.kn;
    c.ks = l.ks;
    c.face_kn = l.face_kn;
    c.face_ks = l.face_ks;
    c.kb = l.kb;
    c.kind = l.kind;
    c.breakable = l.breakable;
    c.faced = l.face_kn != 0.0 || l.face_ks != 0.0;
    const auto same = [&](const LinkClass& o) {
      return o.rest == c.rest && o.kn == c.kn && o.ks == c.ks && o.face_kn == c.face_kn &&
             o.face_ks == c.face_ks && o.kb == c.kb && o.kind == c.kind &&
             o.breakable == c.breakable;
    };
    const auto found = std::find_if(classes_.begin(), classes_.end(), same);
    const int cls = static_cast<int>(found - classes_.begin());
    if (found == classes_.end()) classes_.push_back(c);
    ends_[k] = {l.i, l.j, cls};
  }
  shear_.assign(links_.size(), Eigen::Vector3d::Zero());
  bend_.assign(links_.size(), Eigen::Vector3d::Zero());
  // Incident lists, in link order (critical time step, energies).
  incident_start_.assign(n + 1, 0);
  for (const LatticeLink& l : links_) {
    ++incident_start_[l.i + 1];
    ++incident_start_[l.j + 1];
  }
  for (int b = 0; b < n; ++b) incident_start_[b + 1] += incident_start_[b];
  incident_.resize(incident_start_[n]);
  std::vector<int> fill(incident_start_.begin(), incident_start_.end() - 1);
  for (int k = 0; k < static_cast<int>(links_.size()); ++k) {
    incident_[fill[links_[k].i]++] = 2 * k;
    incident_[fill[links_[k].j]++] = 2 * k + 1;
  }
  // Only the faces of the weak plane need the bodies' orientations (for face contacts).
  oriented_.assign(n, 0);
  if (weak)
    for (int iy = 0; iy < ny_; ++iy)
      for (int ix = 0; ix < nx_; ++ix) {
        oriented_[index(ix, iy, def.weak_layer)] = 1;
        oriented_[index(ix, iy, def.weak_layer - 1)] = 1;
      }
  freedom_.assign(n, 0.0);
  {
    std::vector<std::vector<int>> cross(n);
    for (int k = 0; k < static_cast<int>(links_.size()); ++k)
      if (links_[k].breakable) {
        cross[links_[k].i].push_back(k);
        cross[links_[k].j].push_back(k);
      }
    cross_start_.assign(1, 0);
    for (int b = 0; b < n; ++b) {
      if (cross[b].empty()) continue;
      plane_bodies_.push_back(b);
      cross_links_.insert(cross_links_.end(), cross[b].begin(), cross[b].end());
      cross_start_.push_back(static_cast<int>(cross_links_.size()));
    }
  }

  if (weak) {
    const int upper = nx_ * ny_;
    contact_state_.assign(upper * kStencil * kStencil, {});
    contact_force_.assign(upper * kStencil * kStencil, Eigen::Vector3d::Zero());
    contact_moment_down_.assign(upper * kStencil * kStencil, Eigen::Vector3d::Zero());
    contact_live_.assign(upper, 0);
    contact_centre_.resize(upper);
    for (int u = 0; u < upper; ++u) contact_centre_[u] = {u % nx_, u / nx_};
    // The link (if any) between each upper body and the lower body of each stencil slot.
    stencil_link_.assign(upper * kStencil * kStencil, -1);
    const int half = kStencil / 2;
    const int layer = nx_ * ny_;
    for (int k = 0; k < static_cast<int>(links_.size()); ++k) {
      const LatticeLink& l = links_[k];
      // Every link across the plane, the bulk ones beyond its end included (never in contact,
      // they keep those pairs out of the face contacts).
      if (l.i / layer != def.weak_layer - 1 || l.j / layer != def.weak_layer) continue;
      const int lower = l.i, upper_body = l.j;  // i < j: i lies in the lower layer
      const int ux = upper_body % nx_, uy = (upper_body / nx_) % ny_;
      const int lx = lower % nx_, ly = (lower / nx_) % ny_;
      const int sx = lx - ux + half, sy = ly - uy + half;
      stencil_link_[(ux + nx_ * uy) * kStencil * kStencil + sy * kStencil + sx] = k;
    }
  }
}

double CubicLattice::critical_time_step() const {
  // Gershgorin on the mass-normalised stiffness M^-1/2 K M^-1/2: omega^2 is at most its
  // largest absolute row sum. A link between bodies i and j (unit n, arm a = |d|/2 from each
  // centre) has the blocks K_tt = kn n n^T + ks (I - n n^T), K_tr = ks a [n x] and
  // K_rr = ks a^2 (I - n n^T), each once on the diagonal and once off it.
  const double mi = std::sqrt(mass_ * inertia_);
  double worst = 0.0;
  for (int b = 0; b < size(); ++b) {
    Eigen::Array3d sum_t = Eigen::Array3d::Zero(), sum_r = Eigen::Array3d::Zero();
    for (int k = incident_start_[b]; k < incident_start_[b + 1]; ++k) {
      const LatticeLink& l = links_[incident_[k] / 2];
      const double kn = l.breakable ? (l.kind == 1 ? springs_.kn1 : springs_.kn2)
                                    : l.kn + std::max(0.0, l.face_kn);
      const double ks = l.breakable ? (l.kind == 1 ? springs_.ks1 : springs_.ks2)
                                    : l.ks + std::max(0.0, l.face_ks);
      const Eigen::Vector3d n = (x0_[l.j] - x0_[l.i]).normalized();
      const double arm = 0.5 * l.rest;
      const Eigen::Matrix3d nn = n * n.transpose();
      const Eigen::Matrix3d tt = kn * nn + ks * (Eigen::Matrix3d::Identity() - nn);
      Eigen::Matrix3d cross;
      cross << 0, -n.z(), n.y(), n.z(), 0, -n.x(), -n.y(), n.x(), 0;
      const Eigen::Matrix3d tr = ks * arm * cross;
      const Eigen::Matrix3d rr = (ks * arm * arm + l.kb) * (Eigen::Matrix3d::Identity() - nn);
      sum_t += 2.0 * (tt.cwiseAbs().rowwise().sum().array() / mass_ +
                      tr.cwiseAbs().rowwise().sum().array() / mi);
      sum_r += 2.0 * (rr.cwiseAbs().rowwise().sum().array() / inertia_ +
                      tr.transpose().cwiseAbs().rowwise().sum().array() / mi);
    }
    worst = std::max({worst, sum_t.maxCoeff(), sum_r.maxCoeff()});
  }
  return 2.0 / std::sqrt(worst);
}

void CubicLattice::prescribe(int b, unsigned axes) {
  prescribed_[b] = static_cast<std::uint8_t>(axes & 15u);
}

void CubicLattice::step(double dt) {
  // The first evaluation of a run: forces of the state as it is, no separation increments.
  if (!forces_current_) compute_forces(0.0);
  const int n = size();
  const double c = def_.global_damping;
  const double a = 1.0 - 0.5 * c * dt, b = 1.0 / (1.0 + 0.5 * c * dt);
  double work = 0.0, damp = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : work, damp) if (n >= kParallelMin)
  for (int k = 0; k < n; ++k) {
    // Eqs 48-49 (leapfrog form) with the damping semi-implicit.
    const Eigen::Vector3d vold = v_[k];
    Eigen::Vector3d vnew = (a * vold + (dt / mass_) * f_[k]) * b;
    for (int ax = 0; ax < 3; ++ax)
      if ((prescribed_[k] >> ax) & 1u) {
        vnew[ax] = vold[ax];
        // The reaction the prescribed motion supplies does work on the body.
        work += -f_[k][ax] * vold[ax] * dt;
      }
    damp += c * mass_ * 0.25 * (vold + vnew).squaredNorm() * dt;
    v_[k] = vnew;
    x_[k] += dt * vnew;
    const Eigen::Vector3d wold = w_[k];
    w_[k] = (prescribed_[k] & 8u) ? Eigen::Vector3d::Zero()
                                  : Eigen::Vector3d((a * wold + (dt / inertia_) * m_[k]) * b);
    damp += c * inertia_ * 0.25 * (wold + w_[k]).squaredNorm() * dt;
    const double angle = oriented_[k] ? w_[k].norm() * dt : 0.0;
    if (angle > 0.0) {
      q_[k] = Eigen::Quaterniond(Eigen::AngleAxisd(angle, w_[k].normalized())) * q_[k];
      q_[k].normalize();
    }
  }
  external_work_ += work;
  damping_work_ += damp;
  compute_forces(dt);
}

void CubicLattice::compute_forces(double dt) {
  const int nl = static_cast<int>(links_.size());
  const int n = size();
  const int plane_count = static_cast<int>(plane_bodies_.size());
#pragma omp parallel if (nl >= kParallelMin)
  {
#pragma omp for schedule(static) nowait
    for (int b = 0; b < n; ++b) {
      f_[b].setZero();
      m_[b].setZero();
    }
    // How free each crack-face body is, from the damage of its links across the plane as the
    // last evaluation left them.
#pragma omp for schedule(static)
    for (int p = 0; p < plane_count; ++p) {
      double sum = 0.0;
      for (int e = cross_start_[p]; e < cross_start_[p + 1]; ++e) {
        const LatticeLink& l = links_[cross_links_[e]];
        sum += damage(l.kind == 1 ? limits1_ : limits2_, l.state);
      }
      freedom_[plane_bodies_[p]] = sum / static_cast<double>(cross_start_[p + 1] - cross_start_[p]);
    }
    for (int colour = 0; colour + 1 < static_cast<int>(colour_start_.size()); ++colour) {
      // No two links of a colour share a body: each adds onto its two bodies directly, in
      // any order. The implicit barrier at the end of each loop orders the colours. Items:
      // the connective links four at a time, then one at a time the rest (the breakable ones).
      const int begin = colour_start_[colour];
      const int quad_count = (breakable_start_[colour] - begin) / 4;
      const int singles = begin + 4 * quad_count;
      const int items = quad_count + (colour_start_[colour + 1] - singles);
#pragma omp for schedule(static)
      for (int t = 0; t < items; ++t) {
        if (t < quad_count)
          add_link_forces<4>(begin + 4 * t, dt);
        else
          add_link_forces<1>(singles + (t - quad_count), dt);
      }
    }
  }
  if (!contact_state_.empty()) face_contacts(dt);
  forces_current_ = true;
}

namespace {

/// The part of s in the plane normal to n: a relative velocity's sliding part, or a stored
/// shear separation turned with its link (a link turns by a tiny angle in one step, so
/// dropping the normal component loses only a second-order sliver of the length).
template <class T>
[[gnu::always_inline]] inline Vec3<T> off_axis(const Vec3<T>& s, const Vec3<T>& n) {
  return s - dot(s, n) * n;
}

}  // namespace

template <int W>
void CubicLattice::add_link_forces(int k, double dt) {
  using T = simd::Real<W>;
  int I[W], J[W], K[W];
  const LinkClass* c[W];
  for (int l = 0; l < W; ++l) {
    I[l] = ends_[k + l].i;
    J[l] = ends_[k + l].j;
    K[l] = k + l;
    c[l] = &classes_[ends_[k + l].cls];
  }
  if (W == 1 && c[0]->breakable && links_[k].state.phase == LinkPhase::contact) return;
  auto at = [&](const std::vector<Eigen::Vector3d>& a, const int* idx)
      __attribute__((always_inline)) { return gather3<W>(a.data(), idx); };
  auto put = [&](std::vector<Eigen::Vector3d> & a, const int* idx, const Vec3<T>& v)
      __attribute__((always_inline)) { scatter3<W>(a.data(), idx, v); };
  // The links' classes: as a rule all share one (a colour runs along a row of the grid).
  bool one_class = true;
  for (int l = 1; l < W; ++l) one_class = one_class && c[l] == c[0];
  auto field = [&](double LinkClass::*f) __attribute__((always_inline)) {
    return one_class ? T(c[0]->*f) : simd::load<W>([&](int l) { return c[l]->*f; });
  };
  const Vec3<T> d = at(x_, J) - at(x_, I);
  const T dist = norm(d);
  const Vec3<T> nrm = d * (1.0 / dist);
  const Vec3<T> half = 0.5 * d;
  // Eqs 50-52: relative velocity at the midpoint c (r_i = d/2, r_j = -d/2).
  const Vec3<T> wi = at(w_, I), wj = at(w_, J);
  const Vec3<T> vrel = (at(v_, J) - at(v_, I)) - cross(wj + wi, half);
  const Vec3<T> vs = off_axis(vrel, nrm);
  const Vec3<T> shear = off_axis(at(shear_, K), nrm) + dt * vs;  // eqs 54-55
  put(shear_, K, shear);
  const T dn = dist - field(&LinkClass::rest);  // opening is positive
  Vec3<T> fj;
  if (W > 1 || !c[0]->breakable) {
    // Eqs 1 and 5: connective springs.
    T kn = field(&LinkClass::kn), ks = field(&LinkClass::ks);
    const auto faced = simd::load_mask<W>([&](int l) { return c[l]->faced; });
    if (simd::any(faced)) {
      const T w = 0.5 * simd::load<W>([&](int l) { return freedom_[I[l]] + freedom_[J[l]]; });
      kn = select(faced, kn + w * field(&LinkClass::face_kn), kn);
      ks = select(faced, ks + w * field(&LinkClass::face_ks), ks);
    }
    fj = -kn * dn * nrm - ks * shear;
  } else if constexpr (W == 1) {
    // The cohesive links, one at a time.
    const LinkEnds e = ends_[k];
    LatticeLink& l = links_[k];
    const bool first = c[0]->kind == 1;
    const CohesiveParams& p = first ? cohesive1_ : cohesive2_;
    const double ds = norm(shear);
    double closing = std::numeric_limits<double>::quiet_NaN();  // the paper's: min(dn, 0)
    if (def_.material.compression == Compression::plane) {
      // The plane's own opening here: the mean opening of the two first-neighbour links
      // across it at the ends of this one (i below the plane, j above).
      const int layer = nx_ * ny_;
      const double ja = (x_[e.i + layer] - x_[e.i]).norm() - (x0_[e.i + layer] - x0_[e.i]).norm();
      const double jb = (x_[e.j] - x_[e.j - layer]).norm() - (x0_[e.j] - x0_[e.j - layer]).norm();
      const double jn = 0.5 * (ja + jb);
      closing = std::min(jn, 0.0) * (x0_[e.j].z() - x0_[e.i].z()) / c[0]->rest;
    }
    const CohesiveTraction t =
        cohesive_traction(p, first ? limits1_ : limits2_, dn, ds, l.state, closing);
    // Eqs 27-29: tractions times the effective area, tension pulls j back towards i.
    fj = -p.area * t.tn * nrm;
    if (ds > 0.0) fj = fj - (p.area * t.ts / ds) * shear;
  }
  // Eq. 6: the same moment on i and j (r_i = -r_j, f_i = -f_j).
  const Vec3<T> moment = cross(Vec3<T>{-half.x, -half.y, -half.z}, fj);
  put(f_, J, at(f_, J) + fj);
  put(f_, I, at(f_, I) - fj);
  Vec3<T> on_j = moment, on_i = moment;
  // Bending: connective first neighbours only (never across the weak plane).
  const T kb = field(&LinkClass::kb);
  const auto bends = kb > 0.0;
  if (simd::any(bends)) {
    const Vec3<T> old = at(bend_, K);
    const Vec3<T> bend = select(bends, off_axis(old, nrm) + dt * off_axis(wj - wi, nrm), old);
    put(bend_, K, bend);
    const Vec3<T> couple = -kb * bend;  // on j; its opposite on i
    on_j = select(bends, moment + couple, moment);
    on_i = select(bends, moment - couple, moment);
  }
  put(m_, J, at(m_, J) + on_j);
  put(m_, I, at(m_, I) + on_i);
}

template void CubicLattice::add_link_forces<1>(int, double);
template void CubicLattice::add_link_forces<4>(int, double);

void CubicLattice::face_contacts(double dt) {
  const int up = def_.weak_layer, down = def_.weak_layer - 1;
  const double r = def_.radius;
  const int half = kStencil / 2;
  const int upper_count = nx_ * ny_;
  rotation_.resize(2 * upper_count);
#pragma omp parallel if (upper_count * 25 >= kParallelMin)
  {
#pragma omp for schedule(static)
    for (int u = 0; u < upper_count; ++u) {
      rotation_[u] = q_[index(u % nx_, u / nx_, down)].toRotationMatrix();
      rotation_[upper_count + u] = q_[index(u % nx_, u / nx_, up)].toRotationMatrix();
    }
    // The live link (if any) of each stencil pair: a pair still linked by a connective or
    // cohesive spring does not touch through a contact as well.
#pragma omp for schedule(static)
    for (int u = 0; u < upper_count; ++u) {
      const int ix = u % nx_, iy = u / nx_;
      const int bu = index(ix, iy, up);
      const Eigen::Matrix3d& Ru = rotation_[upper_count + u];
      // The stencil follows the slip of the faces: it is centred on the lower body nearest
      // under this one, walked from last step's (the faces slip far less than a cube a step).
      // Once a beam is split, nothing bounds how far its halves slide along each other.
      int cx = contact_centre_[u][0], cy = contact_centre_[u][1];
      const Eigen::Vector3d& xu = x_[bu];
      const auto dx = [&](int jx) { return std::abs(x_[index(jx, cy, down)].x() - xu.x()); };
      while (cx + 1 < nx_ && dx(cx + 1) < dx(cx)) ++cx;
      while (cx > 0 && dx(cx - 1) < dx(cx)) --cx;
      const auto dy = [&](int jy) { return std::abs(x_[index(cx, jy, down)].y() - xu.y()); };
      while (cy + 1 < ny_ && dy(cy + 1) < dy(cy)) ++cy;
      while (cy > 0 && dy(cy - 1) < dy(cy)) --cy;
      // The slots touching at the last step: every other slot's state is still the zero state
      // (each is reset as it stops touching), unless the stencil moves now.
      std::uint32_t was_live = contact_live_[u];
      if (cx != contact_centre_[u][0] || cy != contact_centre_[u][1]) {
        was_live = ~0u;
        // The same lower bodies keep their contact state in their new slots.
        const int mx = cx - contact_centre_[u][0], my = cy - contact_centre_[u][1];
        std::array<HertzMindlinState, kStencil * kStencil> moved{};
        for (int sy = 0; sy < kStencil; ++sy)
          for (int sx = 0; sx < kStencil; ++sx) {
            const int ox = sx + mx, oy = sy + my;
            if (ox >= 0 && oy >= 0 && ox < kStencil && oy < kStencil)
              moved[sy * kStencil + sx] =
                  contact_state_[u * kStencil * kStencil + oy * kStencil + ox];
          }
        std::copy(moved.begin(), moved.end(), contact_state_.begin() + u * kStencil * kStencil);
        contact_centre_[u] = {cx, cy};
      }
      std::uint32_t live = 0;
      for (int sy = 0; sy < kStencil; ++sy)
        for (int sx = 0; sx < kStencil; ++sx) {
          const int slot = u * kStencil * kStencil + sy * kStencil + sx;
          const int jx = cx + sx - half, jy = cy + sy - half;
          if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) continue;
          const int bd = index(jx, jy, down);
          // A pair with a live spring between them is held by it (links join neighbours in
          // the rest lattice, so by offsets from this body's own column).
          const int ox = jx - ix + half, oy = jy - iy + half;
          const int link = ox >= 0 && oy >= 0 && ox < kStencil && oy < kStencil
                               ? stencil_link_[u * kStencil * kStencil + oy * kStencil + ox]
                               : -1;
          const bool linked = link >= 0 && links_[link].state.phase != LinkPhase::contact;
          HertzMindlinState& state = contact_state_[slot];
          const std::uint32_t bit = 1u << (sy * kStencil + sx);
          const auto untouched = [&] {
            if (was_live & bit) state = {};
          };
          if (linked) {
            untouched();
            continue;
          }
          // Far apart sideways (beyond what any tilt of the faces could bring within reach).
          const Eigen::Vector3d gap = x_[bu] - x_[bd];
          if (std::abs(gap.x()) >= 3.0 * r || std::abs(gap.y()) >= 3.0 * r || gap.z() >= 3.0 * r) {
            untouched();
            continue;
          }
          const Eigen::Matrix3d& Rd = rotation_[jx + nx_ * jy];
          // Mean face normal, from the lower cube (A) towards the upper (B).
          Eigen::Vector3d nrm = Rd.col(2) + Ru.col(2);
          nrm.normalize();
          const Eigen::Vector3d d = x_[bu] - x_[bd];
          const double s = d.dot(nrm);
          const double overlap = 2.0 * r - s;
          const Eigen::Vector3d t = d - s * nrm;
          const double fx = 1.0 - std::abs(t.dot(Rd.col(0))) / (2.0 * r);
          const double fy = 1.0 - std::abs(t.dot(Rd.col(1))) / (2.0 * r);
          if (overlap <= 0.0 || fx <= 0.0 || fy <= 0.0) {
            untouched();
            continue;
          }
          // The axis of least penetration (the separating axes of two nearly aligned cubes):
          // the faces, as a rule; a side face when a cube comes in from the side deeper than it
          // overlaps sideways (a beam's end sliding past the end of the beam below it), which
          // the faces' Hertz law would meet with the full depth at once.
          Eigen::Vector3d axis = nrm;
          double depth = overlap, fraction = fx * fy;
          const double side_x = 2.0 * r * fx, side_y = 2.0 * r * fy;  // sideways overlaps
          if (side_x < depth || side_y < depth) {
            const double fz = std::min(1.0, overlap / (2.0 * r));
            if (side_x <= side_y) {
              axis = (t.dot(Rd.col(0)) >= 0.0 ? 1.0 : -1.0) * Rd.col(0);
              depth = side_x;
              fraction = fz * fy;
            } else {
              axis = (t.dot(Rd.col(1)) >= 0.0 ? 1.0 : -1.0) * Rd.col(1);
              depth = side_y;
              fraction = fz * fx;
            }
          }
          // The contact point: between the faces, over the middle of their common patch.
          const Eigen::Vector3d c = x_[bd] + 0.5 * (s * nrm) + 0.5 * t;
          const Eigen::Vector3d rb = c - x_[bu], ra = c - x_[bd];
          const Eigen::Vector3d vrel = (v_[bu] + w_[bu].cross(rb)) - (v_[bd] + w_[bd].cross(ra));
          const HertzMindlinForce hm = hertz_mindlin_force(hertz_, depth, axis, vrel, state, dt);
          const Eigen::Vector3d fb = fraction * hm.force;
          live |= bit;
          // The upper body is this loop's own: its slots add onto it here, in slot order.
          f_[bu] += fb;
          m_[bu] += rb.cross(fb);
          contact_force_[slot] = fb;
          contact_moment_down_[slot] = ra.cross(-fb);
        }
      contact_live_[u] = live;
    }
  }
  // The lower bodies' reactions, serially in a fixed order (any thread count sums alike): the
  // upper bodies in turn, each its touching slots in slot order.
  for (int u = 0; u < upper_count; ++u) {
    const int cx = contact_centre_[u][0], cy = contact_centre_[u][1];
    for (std::uint32_t live = contact_live_[u]; live != 0; live &= live - 1) {
      const int s = std::countr_zero(live);
      const int slot = u * kStencil * kStencil + s;
      const int bd = index(cx + s % kStencil - half, cy + s / kStencil - half, down);
      f_[bd] -= contact_force_[slot];
      m_[bd] += contact_moment_down_[slot];
    }
  }
}

double CubicLattice::link_elastic_energy(std::size_t k) const {
  const LatticeLink& l = links_[k];
  if (l.state.phase != LinkPhase::connective) return 0.0;
  const double w =
      l.face_kn != 0.0 || l.face_ks != 0.0 ? 0.5 * (freedom_[l.i] + freedom_[l.j]) : 0.0;
  const double kn =
      l.breakable ? (l.kind == 1 ? springs_.kn1 : springs_.kn2) : l.kn + w * l.face_kn;
  const double ks =
      l.breakable ? (l.kind == 1 ? springs_.ks1 : springs_.ks2) : l.ks + w * l.face_ks;
  const double dn = (x_[l.j] - x_[l.i]).norm() - l.rest;
  return 0.5 * kn * dn * dn + 0.5 * ks * shear_[k].squaredNorm() +
         0.5 * l.kb * bend_[k].squaredNorm();
}

LatticeEnergy CubicLattice::energy() const {
  LatticeEnergy e;
  for (int b = 0; b < size(); ++b)
    e.kinetic += 0.5 * mass_ * v_[b].squaredNorm() + 0.5 * inertia_ * w_[b].squaredNorm();
  for (std::size_t k = 0; k < links_.size(); ++k) e.elastic += link_elastic_energy(k);
  return e;
}

double CubicLattice::body_elastic_energy(int b) const {
  double e = 0.0;
  for (int a = incident_start_[b]; a < incident_start_[b + 1]; ++a)
    e += 0.5 * link_elastic_energy(static_cast<std::size_t>(incident_[a] / 2));
  return e;
}

CubicLattice::PhaseCounts CubicLattice::phase_counts() const {
  PhaseCounts c;
  for (const LatticeLink& l : links_) {
    if (!l.breakable) continue;
    switch (l.state.phase) {
      case LinkPhase::connective:
        ++c.connective;
        break;
      case LinkPhase::cohesive:
        ++c.cohesive;
        break;
      case LinkPhase::contact:
        ++c.contact;
        break;
    }
  }
  return c;
}

double CubicLattice::crack_front_x(bool contact_only) const {
  double front = 0.0;
  for (const LatticeLink& l : links_) {
    if (!l.breakable || l.state.phase == LinkPhase::connective) continue;
    if (contact_only && l.state.phase != LinkPhase::contact) continue;
    front = std::max(front, 0.5 * (x0_[l.i].x() + x0_[l.j].x()));
  }
  return front;
}

std::uint64_t CubicLattice::state_hash() const {
  std::uint64_t h = 1469598103934665603ULL;
  for (int b = 0; b < size(); ++b) {
    hash_bytes(h, x_[b].data(), sizeof(double) * 3);
    hash_bytes(h, v_[b].data(), sizeof(double) * 3);
    hash_bytes(h, w_[b].data(), sizeof(double) * 3);
  }
  for (std::size_t k = 0; k < links_.size(); ++k) {
    const LatticeLink& l = links_[k];
    hash_bytes(h, shear_[k].data(), sizeof(double) * 3);
    hash_bytes(h, bend_[k].data(), sizeof(double) * 3);
    hash_bytes(h, &l.state.lambda_max, sizeof(double));
    hash_bytes(h, &l.state.dc, sizeof(double));  // the traction rule's own dc (else 0)
    const auto phase = static_cast<std::uint8_t>(l.state.phase);
    hash_bytes(h, &phase, 1);
  }
  return h;
}

}  // namespace cleave::physics

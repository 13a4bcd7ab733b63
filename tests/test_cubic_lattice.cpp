// The connective lattice of seed 002 (sec. 2): eq. 3's springs reproduce the isotropic solid
// under homogeneous strain (Cauchy-Born), a cohesive link dissipates G_c times its area, cube
// faces touch by Hertz's law over their common patch, and the run is deterministic.
#include <gtest/gtest.h>
#include <omp.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "io/validation_scenario.hpp"
#include "validation/beam_test_rig.hpp"
#include "physics/lattice/cubic_lattice.hpp"

using namespace cleave::physics;

namespace {

LatticeMaterial paper_material() {
  LatticeMaterial m;
  m.young = 120e9;
  m.poisson = 0.2;
  m.density = 2500.0;
  m.sigma_c = 70e6;
  m.g_c = 260.0;
  return m;
}

/// Drives every body of `lat` along v(x0) = eps x0 / T for `steps` steps (all prescribed,
/// spins held: the Cauchy-Born state of a symmetric strain has no rotation), so the lattice
/// ends strained by eps, shear springs included.
void strain(CubicLattice& lat, const Eigen::Matrix3d& eps, int steps, double dt) {
  const double T = steps * dt;
  for (int b = 0; b < lat.size(); ++b) {
    lat.prescribe(b, 15u);
    const Eigen::Vector3d v = eps * lat.rest_positions()[b] / T;
    for (int a = 0; a < 3; ++a) lat.set_velocity(b, a, v[a]);
  }
  for (int i = 0; i < steps; ++i) lat.step(dt);
}

/// The strain energy density of the isotropic solid, lambda (tr e)^2 / 2 + mu e:e.
double isotropic_energy_density(const Eigen::Matrix3d& e, double E, double nu) {
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  return 0.5 * lambda * e.trace() * e.trace() + mu * (e.array() * e.array()).sum();
}

/// The paper's DCB (sec. 7.1: 30 x B x 2 mm, a0 = 9 mm, r = 0.125 mm) as a rig definition.
BeamRigDef paper_dcb(double breadth) {
  BeamRigDef rig;
  rig.kind = BeamTestKind::dcb;
  rig.radius = 0.125e-3;
  rig.length = 30e-3;
  rig.breadth = breadth;
  rig.height = 2e-3;
  rig.initial_crack = 9e-3;
  rig.material = paper_material();
  return rig;
}

/// Two layers of nx cubes (one across) either side of a weak plane that starts decohered
/// everywhere: the set-up of the crack-face contact tests.
CubicLatticeDef decohered_layers(int nx) {
  CubicLatticeDef def;
  def.nx = nx;
  def.ny = 1;
  def.nz = 2;
  def.radius = 0.125e-3;
  def.material = paper_material();
  def.weak_layer = 1;
  def.notch_x = 1.0;  // everything across the plane starts in contact
  return def;
}

/// Eq. 34 between two of the paper's cubes face to face (E* of equal solids, r* = r/2).
double hertz_force(double r, double overlap) {
  const double E_star = 1.0 / (2 * (1 - 0.04) / 120e9);
  return 4.0 / 3.0 * E_star * std::sqrt(r / 2) * std::pow(overlap, 1.5);
}

}  // namespace

TEST(LatticeSprings, Eq3StiffnessesAndEffectiveAreas) {
  const double E = 120e9, nu = 0.2, r = 0.125e-3;
  const LatticeSprings s = lattice_springs(E, nu, r);
  EXPECT_DOUBLE_EQ(s.kn1, 2 * E * r / (5 * (1 - 2 * nu)));
  EXPECT_DOUBLE_EQ(s.kn2, s.kn1);
  EXPECT_DOUBLE_EQ(s.ks1, 2 * E * r * (1 - 4 * nu) / (5 * (1 - 2 * nu) * (1 + nu)));
  EXPECT_DOUBLE_EQ(s.ks2, s.ks1);
  EXPECT_DOUBLE_EQ(s.area1, M_PI * r * r / 4);
  EXPECT_DOUBLE_EQ(s.area2, 2 * M_PI * r * r / 9);
}

TEST(LatticeSprings, TiledAreasShareOutTheCellFaceAmongTheLinksAcrossAPlane) {
  // Whatever crosses a plane between two layers of a bulk body's column must carry the cell
  // face (2r)^2: then a crack there dissipates G_c per unit area. Sum the areas of the links
  // the lattice actually builds from the middle body of a 3 x 3 x 2 block to the layer above.
  CubicLatticeDef def;
  def.nx = def.ny = 3;
  def.nz = 2;
  def.radius = 0.125e-3;
  def.material = paper_material();
  def.weak_layer = 1;
  const double r = def.radius;
  for (const bool tiled : {true, false}) {
    def.tiled_areas = tiled;
    CubicLattice lat(def);
    const int centre = lat.index(1, 1, 0);
    const LatticeSprings paper = lattice_springs(def.material.young, def.material.poisson, r);
    double area = 0.0;
    int crossing = 0;
    for (const LatticeLink& l : lat.links()) {
      if (!l.breakable || (l.i != centre && l.j != centre)) continue;
      ++crossing;
      area += l.kind == 1 ? lat.springs().area1 : lat.springs().area2;
    }
    EXPECT_EQ(crossing, 5);  // one first and four second neighbours (no third: k = 0)
    if (tiled) {
      EXPECT_NEAR(area, 4 * r * r, 1e-12 * r * r);
      EXPECT_DOUBLE_EQ(lat.springs().area1 / lat.springs().area2, paper.area1 / paper.area2);
    } else {
      EXPECT_NEAR(area, 41 * M_PI / 36 * r * r, 1e-12 * r * r);  // 0.894 of the face
      EXPECT_DOUBLE_EQ(lat.springs().area1, paper.area1);
    }
  }
}

TEST(BeamLattice, TheNotchEndsAtTheCrackLengthWhateverTheRoundingOfRPlusA0) {
  // The paper's DCB: r = 0.125 mm, a0 = 9 mm from the load line at x = r. The link at the
  // crack tip (column 36, centre x = 73 r) lies exactly at r + a0, which in double rounds
  // to one ulp above 73 r: it must stay connective, with everything before it decohered.
  // Checked in whole cells against every link across the plane.
  BeamRigDef rig = paper_dcb(2e-3);
  for (const double a0_mm : {9.0, 6.0, 12.0, 8.75}) {
    rig.initial_crack = a0_mm * 1e-3;
    CubicLattice lat(beam_lattice(rig));
    const long tip2 = std::lround(2 * a0_mm / 0.25);  // twice the tip column
    int cut = 0, intact = 0;
    for (const LatticeLink& l : lat.links()) {
      if (!l.breakable) continue;
      const long ix = l.i % lat.def().nx, jx = l.j % lat.def().nx;
      const bool before = ix + jx < tip2;  // midpoint column < tip column
      EXPECT_EQ(l.state.phase == LinkPhase::contact, before) << "a0 " << a0_mm << " link " << ix << "-" << jx;
      (before ? cut : intact) += 1;
    }
    EXPECT_GT(cut, 0);
    EXPECT_GT(intact, 0);
  }
}

TEST(BeamLattice, TheWeakPlaneEndsWhereTheIntactBeamBegins) {
  // A DCB 30 mm long with 3 mm of intact beam beyond it: every link across the mid-plane
  // up to the weak plane's last column (centre x = 30 mm - r) may crack, none beyond it,
  // and those beyond it are bulk links (first neighbours get bending springs).
  BeamRigDef rig = paper_dcb(0.5e-3);
  rig.intact_length = 3e-3;
  const CubicLatticeDef def = beam_lattice(rig);
  EXPECT_EQ(def.nx, 132);  // 120 + 12 columns of 0.25 mm
  CubicLattice lat(def);
  const int layer = def.nx * def.ny;
  int weak = 0, bulk = 0;
  for (const LatticeLink& l : lat.links()) {
    if (l.i / layer != def.weak_layer - 1 || l.j / layer != def.weak_layer) continue;
    const long ix = l.i % def.nx, jx = l.j % def.nx;
    const bool within = ix + jx <= 2 * 119;  // midpoint at or before column 119
    EXPECT_EQ(l.breakable, within) << "link " << ix << "-" << jx;
    if (!within && l.kind == 1) {
      EXPECT_GT(l.kb, 0.0) << "bulk link " << ix << "-" << jx;
    }
    (within ? weak : bulk) += 1;
  }
  EXPECT_GT(weak, 0);
  EXPECT_GT(bulk, 0);
  BeamTestRig dcb(rig);
  EXPECT_DOUBLE_EQ(dcb.analytic().L, 29.75e-3);  // load line to the last weak column
  EXPECT_DOUBLE_EQ(beam_analytic(rig).L, 29.75e-3);  // the same without building the lattice
  rig.kind = BeamTestKind::enf;
  EXPECT_THROW(beam_lattice(rig), std::invalid_argument);
}

TEST(BeamLattice, TheLoadReadIsTheMeanOfEveryStepsLoadSinceItsWindowBegan) {
  // The rig's reading averages the load and Delta over the steps of its window: check it
  // against the mean of the instantaneous values read after each of those steps.
  BeamRigDef rig = paper_dcb(0.5e-3);
  rig.velocity = 0.075;  // eq. 56's v0, at once
  rig.ramp_time = 0.0;
  BeamTestRig dcb(rig);
  for (int i = 0; i < 100; ++i) dcb.step();
  dcb.restart_load_window();
  const BeamReading empty = dcb.reading();  // no step in the window: the instantaneous values
  EXPECT_EQ(empty.load, empty.load_instant);
  EXPECT_EQ(empty.delta, empty.delta_instant);
  double load = 0.0, delta = 0.0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    dcb.step();
    const BeamReading r = dcb.reading();
    load += r.load_instant;
    delta += r.delta_instant;
  }
  const BeamReading r = dcb.reading();
  EXPECT_NEAR(r.load, load / n, 1e-12 * std::abs(r.load_instant));
  EXPECT_NEAR(r.delta, delta / n, 1e-12 * std::abs(r.delta_instant));
  // The grips move apart: the window's mean Delta lies below its last value.
  EXPECT_GT(r.load_instant, 0.0);
  EXPECT_NE(r.load, r.load_instant);
  EXPECT_LT(r.delta, r.delta_instant);
}

class CauchyBorn : public ::testing::TestWithParam<int> {};

TEST_P(CauchyBorn, ABulkBodyStoresTheIsotropicStrainEnergyOfItsCell) {
  // Eq. 3 is derived so that the springs of the cubic cell store the strain energy of the
  // isotropic solid (E, nu) under any homogeneous strain: check a bulk body's share.
  const double E = 120e9, nu = 0.2, r = 0.125e-3;
  Eigen::Matrix3d eps = Eigen::Matrix3d::Zero();
  switch (GetParam()) {
    case 0:
      eps(0, 0) = 1e-5;
      break;  // uniaxial strain
    case 1:
      eps(0, 1) = eps(1, 0) = 1e-5;
      break;  // simple shear (xy)
    case 2:
      eps.diagonal() << 1e-5, -0.3e-5, 0.6e-5;
      break;  // triaxial
    case 3:
      eps << 1e-5, 0.4e-5, -0.2e-5, 0.4e-5, -0.5e-5, 0.3e-5, -0.2e-5, 0.3e-5, 0.8e-5;
      break;
  }
  CubicLatticeDef def;
  def.nx = def.ny = def.nz = 5;
  def.radius = r;
  def.material = paper_material();
  CubicLattice lat(def);
  strain(lat, eps, 200, 1e-9);
  const int centre = lat.index(2, 2, 2);
  const double cell = std::pow(2 * r, 3);
  const double expected = isotropic_energy_density(eps, E, nu) * cell;
  EXPECT_NEAR(lat.body_elastic_energy(centre), expected, 1e-4 * expected);
  // And the bulk is in equilibrium: a homogeneous strain leaves no net force on it.
  EXPECT_LT(lat.forces()[centre].norm(), 1e-6 * lattice_springs(E, nu, r).kn1 * 1e-5 * r);
}

INSTANTIATE_TEST_SUITE_P(Strains, CauchyBorn, ::testing::Values(0, 1, 2, 3));

TEST(CohesiveLatticeLink, PullingTwoCubesApartDissipatesGcTimesTheEffectiveArea) {
  // Two cubes stacked across the weak plane, one first-neighbour link between them (eq. 3,
  // A = the lattice's first-neighbour area). The work to open it to decohesion is A (G_c + sigma_c dn0 / 2).
  CubicLatticeDef def;
  def.nx = def.ny = 1;
  def.nz = 2;
  def.radius = 0.125e-3;
  def.material = paper_material();
  def.material.g_c = 2.0;  // a short softening branch: fewer steps
  def.weak_layer = 1;
  CubicLattice lat(def);
  ASSERT_EQ(lat.links().size(), 1u);
  const LatticeSprings s = lat.springs();
  const double dn0 = s.area1 * def.material.sigma_c / s.kn1;
  const double dc = dn0 + 2 * def.material.g_c / def.material.sigma_c;
  lat.prescribe(0, 7u);
  lat.prescribe(1, 7u);
  const int steps = 20000;
  const double dt = 1e-9, v = 1.1 * dc / (steps * dt);
  lat.set_velocity(1, 2, v);
  double work = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double before = lat.forces()[1].z();
    lat.step(dt);
    work -= 0.5 * (before + lat.forces()[1].z()) * v * dt;
  }
  EXPECT_EQ(lat.links()[0].state.phase, LinkPhase::contact);
  const double expected = s.area1 * (def.material.g_c + 0.5 * def.material.sigma_c * dn0);
  EXPECT_NEAR(work, expected, 2e-3 * expected);
  EXPECT_NEAR(lat.external_work(), expected, 2e-3 * expected);
}

namespace {

struct PlaneLaw {
  double peak = 0;  ///< largest traction on the plane (Pa)
  double work = 0;  ///< work per unit area of plane to move delta_max (N/m)
};

/// The weak plane's own traction-separation law: two layers of 5 x 5 cubes, the lower held,
/// the upper moved rigidly along `axis` (0: slip, 2: opening) to delta_max, spins held; read
/// on the middle upper cube, whose five links down are one cell of the plane.
PlaneLaw sheared_or_opened_plane(int axis, Compression compression, double delta_max) {
  CubicLatticeDef def;
  def.nx = def.ny = 5;
  def.nz = 2;
  def.radius = 0.125e-3;
  def.material = paper_material();
  def.material.g_c = 1002.0;  // G_IIc of the ENF
  def.material.compression = compression;
  def.weak_layer = 1;
  def.link_bending = 1.5;
  CubicLattice lat(def);
  for (int b = 0; b < lat.size(); ++b) lat.prescribe(b, 15u);
  const int steps = 20000;
  const double dt = 1e-9, v = delta_max / (steps * dt), area = 4 * def.radius * def.radius;
  for (int iy = 0; iy < 5; ++iy)
    for (int ix = 0; ix < 5; ++ix) lat.set_velocity(lat.index(ix, iy, 1), axis, v);
  const int middle = lat.index(2, 2, 1);
  PlaneLaw law;
  double prev = 0.0;
  for (int i = 0; i < steps; ++i) {
    lat.step(dt);
    const double t = -lat.forces()[middle][axis] / area;
    law.work += 0.5 * (prev + t) * v * dt;
    law.peak = std::max(law.peak, t);
    prev = t;
  }
  return law;
}

}  // namespace

TEST(WeakPlane, OpenedOrShearedItPeaksAtSigmaCAndPartsWithGcWhenOnlyItsClosingIsCompression) {
  // A cell of plane holds one first-neighbour link and four second neighbours, whose areas
  // tile it (tiled_areas): opened, each parts with A G_c, so the plane with G_c per unit area
  // (plus the little elastic energy before initiation, sigma_c d0 / 2 = 3.4 N/m). Slipped, a
  // second neighbour at 45 degrees either lengthens or shortens by s / sqrt 2; with
  // Compression::plane that shortening separates too, so slip parts the plane with the same
  // G_c and strength: the mode-II law the ENF needs. 4 G_c / sigma_c (57 um) is past every
  // link's decohesion (dc = 28.7 um; a diagonal sees s / sqrt 2 or s).
  const double gc = 1002.0, sigma_c = 70e6, delta = 4.0 * gc / sigma_c;
  for (int axis : {2, 0}) {
    const PlaneLaw law = sheared_or_opened_plane(axis, Compression::plane, delta);
    SCOPED_TRACE(axis == 0 ? "slip" : "opening");
    EXPECT_NEAR(law.peak / sigma_c, 1.0, 0.01);
    EXPECT_NEAR(law.work / gc, 1.0, 0.01);
  }
  // The paper's reading: the shortened diagonals stay in compression as struts until their
  // shear part alone reaches dc (s = sqrt 2 dc = 40 um): the slipped plane carries tens of
  // sigma_c and takes tens of G_c to part. Opening is the same under both readings.
  const PlaneLaw slip = sheared_or_opened_plane(0, Compression::link, delta);
  EXPECT_GT(slip.peak, 10 * sigma_c);
  EXPECT_GT(slip.work, 10 * gc);
  const PlaneLaw open = sheared_or_opened_plane(2, Compression::link, delta);
  EXPECT_NEAR(open.work / gc, 1.0, 0.01);
}

TEST(CubeFaceContact, HertzLawOverTheFacesCommonPatch) {
  // Two cubes across a notch (the link starts decohered): pressed together by delta, the
  // force is eq. 34 with r* = r/2 (equal cubes); shifted sideways by half a side, half of
  // each face touches and the force halves; frictionless, no tangential force.
  const CubicLatticeDef def = decohered_layers(2);
  CubicLattice lat(def);
  const double r = def.radius, delta = 1e-7;
  const double hertz = hertz_force(r, delta);
  for (int b = 0; b < lat.size(); ++b) lat.prescribe(b, 15u);
  // Upper layer down by delta over 100 steps.
  const int top0 = lat.index(0, 0, 1), top1 = lat.index(1, 0, 1);
  for (int b : {top0, top1}) lat.set_velocity(b, 2, -delta / (100 * 1e-9));
  for (int i = 0; i < 100; ++i) lat.step(1e-9);
  EXPECT_NEAR(lat.forces()[top0].z(), hertz, 1e-6 * hertz);
  EXPECT_NEAR(lat.forces()[top0].x(), 0.0, 1e-9 * hertz);
  // Slide the upper layer by r along x: each upper cube now half over each lower one.
  for (int b : {top0, top1}) {
    lat.set_velocity(b, 2, 0.0);
    lat.set_velocity(b, 0, r / (100 * 1e-9));
  }
  for (int i = 0; i < 100; ++i) lat.step(1e-9);
  // top1 now covers half of lower cube 1 only (nothing beyond the edge): half the force.
  EXPECT_NEAR(lat.forces()[top1].z(), 0.5 * hertz, 1e-6 * hertz);
  // top0 straddles lower cubes 0 and 1: two halves.
  EXPECT_NEAR(lat.forces()[top0].z(), hertz, 1e-6 * hertz);
  EXPECT_NEAR(lat.forces()[top0].x(), 0.0, 1e-9 * hertz);
}

TEST(CubicLattice, BitIdenticalForOneAndTwoThreads) {
  // A coarse DCB loaded through crack initiation: the same state hash for 1 and 2 threads.
  const auto v = cleave::io::load_validation_scenario(std::string(CLEAVE_SOURCE_DIR) +
                                                      "/scenarios/validation/dcb_coarse.toml");
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    BeamTestRig rig(v.rig);
    for (int i = 0; i < 3000; ++i) rig.step();
    return rig.lattice().state_hash();
  };
  const auto one = run(1), two = run(2);
  omp_set_num_threads(2);
  EXPECT_EQ(one, two);
}

TEST(CubicLattice, TheLinkLawGivesTheSameBitsAtWidthsOneAndFour) {
  // A coarse DCB loaded through crack initiation, so links carry shear and bending
  // histories and the face links their compensation. From that state every run of four
  // connective links that share no body goes once four at a time and once one at a time,
  // twice over (the second pass reads the histories the first wrote). Each body receives one
  // addition a run either way, in the same order, so its sums agree bit for bit when each
  // lane rounds as one link alone.
  const auto v = cleave::io::load_validation_scenario(std::string(CLEAVE_SOURCE_DIR) +
                                                      "/scenarios/validation/dcb_coarse.toml");
  BeamTestRig rig(v.rig);
  for (int i = 0; i < 1000; ++i) rig.step();
  CubicLattice one = rig.lattice(), four = rig.lattice();
  const auto& links = one.links();
  const double dt = 1e-8;
  std::vector<int> runs;
  int faced = 0, bending = 0;
  for (int k = 0; k + 4 <= static_cast<int>(links.size()); k += 4) {
    bool ok = true;
    for (int l = 0; l < 4 && ok; ++l) {
      ok = !links[k + l].breakable;
      for (int m = 0; m < l && ok; ++m)
        ok = links[k + l].i != links[k + m].i && links[k + l].i != links[k + m].j &&
             links[k + l].j != links[k + m].i && links[k + l].j != links[k + m].j;
    }
    if (!ok) continue;
    runs.push_back(k);
    for (int l = 0; l < 4; ++l) {
      faced += links[k + l].face_kn != 0.0;
      bending += links[k + l].kb > 0.0;
    }
  }
  ASSERT_GT(runs.size(), 1000u);
  EXPECT_GT(faced, 0) << "no face link among the runs: the compensation went unchecked";
  EXPECT_GT(bending, 0) << "no bending spring among the runs";
  for (int pass = 0; pass < 2; ++pass)
    for (const int k : runs) {
      for (int l = 0; l < 4; ++l) one.add_link_forces<1>(k + l, dt);
      four.add_link_forces<4>(k, dt);
    }
  int differ = 0;
  for (int b = 0; b < one.size(); ++b)
    for (int a = 0; a < 3; ++a) {
      differ += std::bit_cast<std::uint64_t>(one.forces()[b][a]) !=
                std::bit_cast<std::uint64_t>(four.forces()[b][a]);
      differ += std::bit_cast<std::uint64_t>(one.moments()[b][a]) !=
                std::bit_cast<std::uint64_t>(four.moments()[b][a]);
    }
  EXPECT_EQ(differ, 0) << "force or moment components that differ in their bits";
}

namespace {

/// Tip stiffness P / delta of a cantilever `cells` layers thick, clamped at its first column
/// and pushed sideways (z) at its last, once the damped lattice has come to rest.
double cantilever_stiffness(int layers, double link_bending, int across = 2) {
  CubicLatticeDef def;
  def.radius = 0.125e-3;
  def.nx = 33;
  def.ny = across;
  def.nz = layers;
  def.material = paper_material();
  def.link_bending = link_bending;
  def.global_damping = 3e6;  // about critical for the first mode
  CubicLattice lat(def);
  const double dt = 0.8 * lat.critical_time_step();
  const double v = 0.05;  // m/s
  const int push = 1500, settle = 6000;
  std::vector<int> tip;
  for (int iz = 0; iz < def.nz; ++iz)
    for (int iy = 0; iy < def.ny; ++iy) {
      lat.prescribe(lat.index(0, iy, iz), 15u);
      const int t = lat.index(def.nx - 1, iy, iz);
      lat.prescribe(t, 4u);
      lat.set_velocity(t, 2, v);
      tip.push_back(t);
    }
  for (int i = 0; i < push; ++i) lat.step(dt);
  for (int t : tip) lat.set_velocity(t, 2, 0.0);
  for (int i = 0; i < settle; ++i) lat.step(dt);
  double load = 0.0;
  for (int t : tip) load -= lat.forces()[t].z();
  return load / (v * push * dt);
}

/// Timoshenko's cantilever: delta = P L^3 / (3 E I) + P L / (k G A), k = 5/6.
double timoshenko_stiffness(int layers, int across = 2) {
  const double E = 120e9, nu = 0.2, G = E / (2 * (1 + nu)), a = 0.25e-3;
  const double L = 32 * a, B = across * a, h = layers * a;
  const double I = B * h * h * h / 12.0, A = B * h;
  return 1.0 / (L * L * L / (3 * E * I) + L / (5.0 / 6.0 * G * A));
}

}  // namespace

TEST(CantileverBending, FourLayersMatchTimoshenkoWithBendingSprings) {
  // The DCB arms of sec. 7 are four cells thick: their stage-I slope is this stiffness.
  const double ratio = cantilever_stiffness(4, 1.0) / timoshenko_stiffness(4);
  std::printf("  4 layers, bending springs: stiffness / Timoshenko = %.4f\n", ratio);
  EXPECT_NEAR(ratio, 1.0, 0.04);
}

TEST(CantileverBending, PointSpringsAloneAreTooSoftAtFourLayers) {
  // The paper's lattice without bending springs: the midpoint rule loses each cell's own
  // bending energy, E (2r)^5 kappa^2 / 24, so the beam is clearly softer than theory.
  const double ratio = cantilever_stiffness(4, 0.0) / timoshenko_stiffness(4);
  std::printf("  4 layers, point springs only: stiffness / Timoshenko = %.4f\n", ratio);
  EXPECT_LT(ratio, 0.95);
  EXPECT_GT(ratio, 0.7);
}

TEST(CantileverBending, ConvergesToTimoshenkoAsTheBeamGetsThicker) {
  const double r4 = cantilever_stiffness(4, 1.0) / timoshenko_stiffness(4);
  const double r8 = cantilever_stiffness(8, 1.0) / timoshenko_stiffness(8);
  std::printf("  stiffness / Timoshenko: 4 layers %.4f, 8 layers %.4f\n", r4, r8);
  EXPECT_LT(std::abs(r8 - 1.0), 0.03);
  EXPECT_LE(std::abs(r8 - 1.0), std::abs(r4 - 1.0) + 0.005);
}

TEST(CantileverBending, WideArmsNeedTheCalibratedSpringsOfTheValidations) {
  // A DCB arm of the validations is 4 cubes thick and 8 across. There the derived springs
  // (multiple 1) leave the beam about 3 % soft (the narrow beam above hides it: its side
  // faces are compensated); scenarios/validation/*.toml use bending_springs = 1.5, which
  // brings this arm within 1 % of Timoshenko.
  const double derived = cantilever_stiffness(4, 1.0, 8) / timoshenko_stiffness(4, 8);
  const double calibrated = cantilever_stiffness(4, 1.5, 8) / timoshenko_stiffness(4, 8);
  std::printf("  4 x 8 arm: stiffness / Timoshenko = %.4f (multiple 1), %.4f (multiple 1.5)\n", derived,
              calibrated);
  EXPECT_LT(derived, 0.98);
  EXPECT_NEAR(calibrated, 1.0, 0.01);
}

TEST(SplitBeamStage, IsJudgedOnlyAfterTheCrackRanThroughAndByItsSlope) {
  // Synthetic readings of the DCB: before the crack reaches L (within h) they lie on a
  // stiffer line, after it on P = s Delta / C with C of eq. 61; the slope is a line's
  // through the origin.
  BeamTest t{BeamTestKind::dcb, 120e9, 0.2, 2e-3, 1e-3, 30e-3, 9e-3, 0.125e-3, 260.0, 1002.0};
  const double C = split_compliance(t);
  for (const double s : {1.0, 1.03, 0.9}) {
    std::vector<BeamReading> curve;
    for (int i = 1; i <= 40; ++i) {
      BeamReading r;
      r.delta = 0.1e-3 * i;
      const bool split = i > 25;
      // Split: decohered to within h = 1 mm of L (the last links still cohesive).
      r.crack = split ? 29.2e-3 : 28.8e-3;
      r.process_zone = 30e-3;
      r.load = (split ? s : 1.4) * r.delta / C;
      curve.push_back(r);
    }
    const StageErrors e = compare_with_closed_form(t, curve, 3, 0.1);
    EXPECT_EQ(e.points, 15);
    EXPECT_NEAR(e.from, 2.6e-3, 1e-12);
    EXPECT_NEAR(e.to, 4.0e-3, 1e-12);
    EXPECT_NEAR(e.slope * C, s, 1e-9);
    EXPECT_NEAR(e.slope_error, std::abs(s - 1.0), 1e-9);
    EXPECT_NEAR(e.mean_error, std::abs(s - 1.0), 1e-9);
  }
  // A crack that never ran through leaves nothing to compare.
  std::vector<BeamReading> stuck(10);
  for (int i = 0; i < 10; ++i) stuck[i] = {0, 0.0, 1e-3 * (i + 1), 1.0 * (i + 1), 28.75e-3, 30e-3};
  const StageErrors none = compare_with_closed_form(t, stuck, 3, 0.1);
  EXPECT_EQ(none.points, 0);
  EXPECT_TRUE(std::isnan(none.slope_error));
}

TEST(CubeFaceContact, FacesSlidFarAlongEachOtherStillTouch) {
  // Two layers of ten cubes, decohered everywhere, pressed together by delta and then slid
  // along each other by five cubes (a split beam's halves slide that far): the upper cubes
  // still over the lower layer feel eq. 34 in full, the ones beyond its end nothing, and
  // the lower cubes under them the reaction.
  const CubicLatticeDef def = decohered_layers(10);
  CubicLattice lat(def);
  const double r = def.radius, delta = 1e-7, dt = 1e-9;
  const double hertz = hertz_force(r, delta);
  for (int b = 0; b < lat.size(); ++b) lat.prescribe(b, 15u);
  for (int ix = 0; ix < 10; ++ix) lat.set_velocity(lat.index(ix, 0, 1), 2, -delta / (100 * dt));
  for (int i = 0; i < 100; ++i) lat.step(dt);
  for (int ix = 0; ix < 10; ++ix) {
    lat.set_velocity(lat.index(ix, 0, 1), 2, 0.0);
    lat.set_velocity(lat.index(ix, 0, 1), 0, 10 * r / (2000 * dt));
  }
  for (int i = 0; i < 2000; ++i) lat.step(dt);
  for (int ix = 0; ix < 10; ++ix) {
    const double f_up = lat.forces()[lat.index(ix, 0, 1)].z();
    const double f_down = lat.forces()[lat.index(ix, 0, 0)].z();
    EXPECT_NEAR(f_up, ix < 5 ? hertz : 0.0, 1e-6 * hertz) << "upper cube " << ix;
    EXPECT_NEAR(f_down, ix >= 5 ? -hertz : 0.0, 1e-6 * hertz) << "lower cube " << ix;
  }
}

TEST(CubeFaceContact, ACubeComingInFromTheSideTouchesByItsSideFace) {
  // One cube over another across a notch: moved sideways off the lower face, down by r/2,
  // then back towards it by e = r/20. Its side face now overlaps the lower cube's by e
  // while its bottom lies r/2 below the lower top face: the least penetration is sideways,
  // so the force is eq. 34 at depth e along x over the side faces' common patch (a quarter
  // of a face: r/2 of its height 2r, all its breadth), with nothing along z.
  const CubicLatticeDef def = decohered_layers(1);
  CubicLattice lat(def);
  lat.prescribe(0, 15u);
  lat.prescribe(1, 15u);
  const double r = def.radius, dt = 1e-9, e = r / 20;
  const auto move = [&](double dx, double dz) {
    lat.set_velocity(1, 0, dx / (100 * dt));
    lat.set_velocity(1, 2, dz / (100 * dt));
    for (int i = 0; i < 100; ++i) lat.step(dt);
  };
  move(2 * r + 0.01 * r, 0.0);
  move(0.0, -0.5 * r);
  EXPECT_EQ(lat.forces()[1].norm(), 0.0);  // beside it, not yet touching
  move(-0.01 * r - e, 0.0);
  const double hertz = hertz_force(r, e);
  EXPECT_NEAR(lat.forces()[1].x(), 0.25 * hertz, 1e-6 * hertz);
  EXPECT_NEAR(lat.forces()[1].z(), 0.0, 1e-9 * hertz);
  EXPECT_NEAR(lat.forces()[0].x(), -0.25 * hertz, 1e-6 * hertz);
}

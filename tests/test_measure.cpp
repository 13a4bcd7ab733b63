// `cleave measure` (sim/measure.hpp) on whole test scenarios of a real material: the
// elastic constants a small-strain uniaxial test reads off a bonded honeycomb are those of
// the triangular lattice's closed form, E scales linearly with the bond stiffness (the
// property `cleave calibrate` relies on), and a scenario that is not the test asked for is
// refused with its name.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "sim/measure.hpp"

namespace fs = std::filesystem;
using namespace cleave;

namespace {

const fs::path kElastic = fs::path(CLEAVE_SOURCE_DIR) / "scenarios/materials/sic_elastic.toml";

sim::Measurement run(sim::Test test, const fs::path& scenario, const std::string& tag,
                     const std::vector<std::string>& overrides = {}) {
  sim::SimulationOptions o;
  o.out = fs::temp_directory_path() / ("cleave_test_measure_" + tag);
  o.quiet = true;
  return sim::measure(test, scenario, o, overrides);
}

}  // namespace

TEST(MaterialTest, ElasticConstantsOfABondedHoneycombAreTheTriangularLatticeClosedForm) {
  const sim::Measurement m = run(sim::Test::elastic, kElastic, "closed_form");
  ASSERT_TRUE(m.closed_form.has_value());
  // The closed form of sic_elastic.toml's springs is alpha-SiC's E and nu (the file's header).
  EXPECT_NEAR(m.closed_form->young / 415e9, 1.0, 1e-3);
  EXPECT_NEAR(m.closed_form->poisson, 0.16, 1e-3);
  EXPECT_NEAR(m.value / m.closed_form->young, 1.0, 0.015) << "E " << m.value;
  EXPECT_NEAR(m.poisson, m.closed_form->poisson, 0.01);
  // The platens also read the give of their corner contacts: a softer specimen.
  EXPECT_LT(m.young_platens, m.value);
  EXPECT_GT(m.young_platens, 0.9 * m.value);
  EXPECT_LT(m.kinetic_ratio, 1e-3) << "not quasi-static";
  EXPECT_GE(m.samples.size(), 20u);
}

TEST(MaterialTest, YoungsModulusScalesLinearlyWithTheBondStiffnessAndPoissonsRatioWithTheirRatio) {
  const sim::Measurement base = run(sim::Test::elastic, kElastic, "stiff");
  // Both bond springs halved: E halves, nu (a function of k_bs / k_bn alone) stays.
  const sim::Measurement soft = run(sim::Test::elastic, kElastic, "soft",
                                    {"bond.kbn=1.816e18", "bond.kbs=0.814e18"});
  EXPECT_NEAR(soft.value / base.value, 0.5, 0.005);
  EXPECT_NEAR(soft.poisson, base.poisson, 0.002);
  // The shear spring alone halved: nu rises as (K_n - K_s) / (3 K_n + K_s) says.
  const sim::Measurement slip = run(sim::Test::elastic, kElastic, "slip", {"bond.kbs=0.814e18"});
  const double expected = physics::honeycomb_elasticity(1.0, 0.5 * 1.628 / 3.632, 1.0).poisson;
  EXPECT_NEAR(slip.poisson, expected, 0.01);
  EXPECT_GT(slip.poisson, base.poisson + 0.03);
}

TEST(MaterialTest, AScenarioThatIsNotTheTestAskedForIsRefusedByName) {
  try {
    (void)run(sim::Test::brazilian, kElastic, "refused");
    FAIL() << "a box was measured as a Brazilian disc";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("sic_elastic.toml: not a brazilian test: its specimen is not a disc"),
              std::string::npos)
        << what;
  }
}

TEST(MaterialTest, BrazilianStrengthScalesLinearlyWithTheBondStrengths) {
  const fs::path disc = fs::path(CLEAVE_SOURCE_DIR) / "scenarios/materials/sic_brazilian.toml";
  const sim::Measurement full = run(sim::Test::brazilian, disc, "brazilian_full");
  const sim::Measurement half = run(sim::Test::brazilian, disc, "brazilian_half",
                                    {"bond.tbn=0.6115e12", "bond.tbs=0.6115e12"});
  // The disc of the scenario is calibrated to alpha-SiC's 250 MPa (its header).
  EXPECT_NEAR(full.value / 250e6, 1.0, 0.03) << full.value;
  EXPECT_NEAR(half.value / full.value, 0.5, 0.03);
  EXPECT_NEAR(full.value, 2.0 * full.peak_load / (M_PI * 8e-3 * 1e-3), 1e-9 * full.value);
}

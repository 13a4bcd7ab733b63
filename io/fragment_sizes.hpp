#pragma once
/// \file
/// Fragment size statistics: the cumulative mass fraction passing against the equivalent
/// diameter, its Rosin-Rammler (Weibull) fit, the power-law exponent of the cumulative number
/// of fragments, fragment_sizes.csv and its picture, and the pooling of several runs' tables
/// (a sweep). A fragment here is a cluster of bodies held together by intact bonds
/// (sim::bonded_fragments makes them); this file only needs each cluster's size.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/plot.hpp"

namespace cleave::io {

/// One fragment: a cluster of `bodies` bodies joined by intact bonds.
struct FragmentRecord {
  std::size_t bodies = 1;
  double volume = 0.0;  ///< m^3
  double mass = 0.0;    ///< kg
};

/// The diameter of the sphere of volume `volume`: d = (6 V / pi)^(1/3).
double equivalent_diameter(double volume);

/// Rosin-Rammler law of the mass fraction passing, P(d) = 1 - exp(-(d / d0)^n) (a Weibull
/// distribution of the mass over d).
struct RosinRammlerFit {
  double d0 = 0.0;  ///< size scale, m (63.2 % of the mass is finer)
  double n = 0.0;   ///< uniformity index
};
/// Maximum likelihood of the Rosin-Rammler law for the mass: each fragment's diameter d_i
/// counts with its mass w_i (the likelihood of the mass's distribution over d, Weibull's
/// density weighted by mass). n solves 1/n + sum w ln d / sum w - sum w d^n ln d / sum w d^n
/// = 0 (bisection on ln n), then d0 = (sum w d^n / sum w)^(1/n). Nothing with fewer than two
/// distinct diameters, or when n would lie outside [1e-3, 1e3] (sizes all but equal).
std::optional<RosinRammlerFit> fit_rosin_rammler(const std::vector<double>& d,
                                                 const std::vector<double>& weight);

/// Power law of the cumulative number, N(> d) ~ d^-b, over its scaling range d >= d_min.
struct PowerLawFit {
  double b = 0.0;            ///< exponent of N(> d)
  double d_min = 0.0;        ///< lower end of the scaling range, m
  double d_max = 0.0;        ///< the largest fragment, m
  std::size_t points = 0;    ///< fragments in the range
  double ks_distance = 0.0;  ///< Kolmogorov-Smirnov distance of the fit in the range
};
/// Clauset, Shalizi and Newman (SIAM Review 51, 2009): for each candidate d_min the maximum
/// likelihood exponent of the tail d >= d_min, b = k / sum ln(d_i / d_min) (their eq. 3.1
/// with alpha = b + 1), and the d_min whose fit is nearest the tail's empirical distribution
/// (least Kolmogorov-Smirnov distance, their sec. 3.3). Tails of fewer than `min_points`
/// fragments are not candidates; nothing when none is (or all diameters are equal).
std::optional<PowerLawFit> fit_power_law(std::vector<double> d, std::size_t min_points = 10);

/// The size distribution of one run (or of several pooled).
struct FragmentSizes {
  std::vector<FragmentRecord> fragments;  ///< by increasing diameter
  std::vector<double> diameter;           ///< m, per fragment
  /// Per fragment: the mass fraction in fragments of diameter <= its own (equal diameters
  /// share the value of the last of them).
  std::vector<double> passing;
  double total_mass = 0.0, total_volume = 0.0;
  double largest_mass_fraction = 0.0;  ///< the heaviest fragment's share of the mass
  std::optional<RosinRammlerFit> rosin_rammler;
  std::optional<PowerLawFit> power_law;
};
FragmentSizes analyse_fragment_sizes(std::vector<FragmentRecord> fragments);

/// fragment_sizes.csv: one row per fragment, by increasing diameter (bodies, volume_m3,
/// mass_kg, diameter_m, passing), then comment lines with the fits.
std::string fragment_sizes_csv(const FragmentSizes& sizes);
/// The fragments of a fragment_sizes.csv (for pooling). Throws std::runtime_error naming the
/// file and line of a malformed row.
std::vector<FragmentRecord> read_fragment_sizes_csv(const std::filesystem::path& path);
/// Cumulative mass fraction passing against log10(d / mm), with the Rosin-Rammler curve.
Plot fragment_sizes_plot(const FragmentSizes& sizes, const std::string& title);
/// run.toml facts: fragments.count, fragments.largest_mass_fraction,
/// fragments.rosin_rammler_d0_m, fragments.rosin_rammler_n, fragments.power_law_exponent,
/// fragments.power_law_d_min_m, fragments.power_law_points (the fits' when there are).
void add_fragment_facts(std::map<std::string, std::string>& facts, const FragmentSizes& sizes);

/// A sweep's runs pooled by group (the values of the keys that are not seeds): `runs` maps
/// each group's label to its runs' result folders. Writes fragments_pooled.csv (per group:
/// runs, fragments, mean fragments per run, mean largest mass fraction, the pooled fits),
/// fragment_sizes_pooled.csv (the pooled distributions, a group column first) and
/// fragments_pooled.svg (one curve per group). Folders without fragment_sizes.csv are
/// skipped; returns the names of the files written (none when no run had one).
std::vector<std::string> write_pooled_fragment_sizes(
    const std::filesystem::path& out,
    const std::vector<std::pair<std::string, std::vector<std::filesystem::path>>>& runs);

}  // namespace cleave::io

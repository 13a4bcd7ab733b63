#pragma once
/// \file
/// Parameter sweeps (`cleave sweep`): `--set KEY=VALUES` specifications, their Cartesian
/// product, each combination written into the scenario's TOML text, and the Weibull fit of a
/// seed ensemble's strengths.
///
/// KEY is a dotted path into the scenario: `table.key` (`bond.tbn`), `table.sub.key`
/// (`contact.particle_particle.kn`), or `stage[N].key` for the N-th `[[stage]]` (1-based).
/// VALUES is a comma list (`1000,2000,4000`) or an inclusive integer range (`1..20`). A value
/// that reads as an integer is written as one, then a floating-point number, then true/false;
/// anything else is written as a string (`"250 MPa"`: a value with its unit).
///
/// `--set` axes combine as a product; `--zip` axes vary together (the i-th value of each in
/// the same run), the zipped group being one factor of the product.
///
/// A ratio axis `KEY/REF=VALUES` (`bond.tbn/fracture.sigma_f=0.1,1,10`) sets KEY to each value
/// times REF's value as the scenario holds it after the plain axes are set: a dimensionless
/// axis. REF must be written in the file (or set by another axis) as a number or a number with
/// its unit ("250 MPa": KEY gets "25 MPa"). REF `fracture.cleavage_strength` is the grains'
/// cleavage strength, which no file writes: sigma_f of a stress criterion, K_Ic / sqrt(pi a)
/// of `lefm` (KEY gets it in Pa).
/// `cleave run --set KEY=VALUE` and Python's `overrides=` take one value per key.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/scenario.hpp"

namespace cleave::io {

/// A bad --set specification or a key the scenario cannot take; the message names them.
class SweepError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The derived ratio reference: the grains' cleavage strength (see the file's comment).
inline constexpr std::string_view kCleavageStrength = "fracture.cleavage_strength";

/// One `--set KEY=VALUES`.
struct SweepAxis {
  std::string key;                  ///< as given, e.g. "orientation.seed"
  std::vector<std::string> values;  ///< as given, e.g. {"1", "2", "3"}
  bool zipped = false;              ///< a --zip axis: varies together with the other zipped ones
  /// A ratio axis: the key its values multiply (e.g. "fracture.sigma_f"); empty: plain values.
  std::string reference;
  /// "key", or for a ratio axis "key/reference": its name in errors and summary.csv.
  std::string name() const { return reference.empty() ? key : key + "/" + reference; }
};

/// Parses "KEY=VALUES"; throws SweepError naming the specification.
SweepAxis parse_sweep_axis(const std::string& spec);

/// One combination: the i-th value of each axis, in axis order.
using SweepPoint = std::vector<std::string>;

/// The Cartesian product of the axes, the last axis varying fastest, the zipped axes taken as
/// one (at the place of the first). Throws SweepError when it would exceed `limit` runs or
/// when zipped axes differ in their number of values.
std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes,
                                     std::size_t limit = 10000);

/// The scenario text with each axis' key set to the point's value (tables are created when
/// missing; an array of tables must exist and be long enough). Relative `file` paths of
/// `[[mesh_grain]]` tables are made absolute against `base_dir` (the original scenario's
/// folder), so the text can be written anywhere. `source` names the scenario in errors.
/// Ratio axes are set after the plain ones, in their order; `absolute`, when given, gets each
/// axis' value as written (a ratio axis': its ratio times the reference's value).
std::string apply_sweep_point(const std::string& scenario_text, const std::string& source,
                              const std::vector<SweepAxis>& axes, const SweepPoint& point,
                              const std::filesystem::path& base_dir,
                              std::vector<std::string>* absolute = nullptr);

/// Overrides ("KEY=VALUE", one value each, as `cleave run --set` takes them) as axes and
/// the one point they make. `label` names them in errors ("--set"). Throws SweepError.
std::pair<std::vector<SweepAxis>, SweepPoint> parse_overrides(
    const std::vector<std::string>& overrides, std::string_view label);

/// Scenario `text` (named `source`) with the point's values set (apply_sweep_point), read.
/// `shown[k]` names axis k's value in errors, e.g. "--set dynamics.dt=abc". An error at a
/// key an axis sets names that value instead of a line (ScenarioError::in_override); an error
/// of the file itself keeps its line; an error the values cause elsewhere (grain.r set below
/// grain.r_bar) names the file, the key and the values. `text_as_run` gets the text read.
Scenario read_sweep_point(const std::string& text, const std::string& source,
                          const std::vector<SweepAxis>& axes, const SweepPoint& point,
                          const std::vector<std::string>& shown,
                          const std::filesystem::path& base_dir,
                          std::string* text_as_run = nullptr);

/// Reads a scenario text (named `source`), throwing ScenarioError: parse_scenario, or another
/// format's reader (parse_validation_scenario).
using ScenarioReader = std::function<void(const std::string& text, const std::string& source)>;

/// read_sweep_point for any format: the text as run, checked by `read` with the same blame
/// of errors; `absolute` as apply_sweep_point's.
std::string check_sweep_point(const std::string& text, const std::string& source,
                              const std::vector<SweepAxis>& axes, const SweepPoint& point,
                              const std::vector<std::string>& shown,
                              const std::filesystem::path& base_dir, const ScenarioReader& read,
                              std::vector<std::string>* absolute = nullptr);

/// Count, mean and sample standard deviation of the finite values (NaN skipped):
/// mean = sum x_i / n, sd = sqrt(sum (x_i - mean)^2 / (n - 1)); sd is NaN for n < 2, and
/// mean too for n = 0.
struct SampleStats {
  std::size_t count = 0;
  double mean = 0.0, stddev = 0.0;
};
SampleStats sample_stats(const std::vector<double>& values);

/// summary_mean.csv from summary.csv's cells: the rows grouped by equal cells in
/// `group_columns` (groups in order of first appearance), only rows with `counted[r]` taking
/// part; a row per group with its group cells, `runs` (rows in the group), `counted`, and for
/// each of `value_columns` NAME_mean, NAME_sd, NAME_n (sample_stats of its numeric cells;
/// empty where undefined).
std::string replicate_means_csv(const std::vector<std::string>& header,
                                const std::vector<std::vector<std::string>>& rows,
                                const std::vector<std::size_t>& group_columns,
                                const std::vector<std::size_t>& value_columns,
                                const std::vector<bool>& counted);

/// The scalar values of a flat TOML file (measure.toml) as text, numbers as written by
/// {:.9g}; an empty map when it cannot be read.
std::map<std::string, std::string> read_flat_toml(const std::filesystem::path& file);

/// `e`, an error of a scenario read with the point's values set, told about them as
/// read_sweep_point does (the rewritten text's lines mean nothing to a user).
ScenarioError blame_sweep_point(const ScenarioError& e, const std::vector<SweepAxis>& axes,
                                const std::vector<std::string>& shown);

/// A two-parameter Weibull fit of strengths, P_f(s) = 1 - exp(-(s / s0)^m), by least squares
/// of ln(-ln(1 - F_i)) on ln(s_i) with the strengths sorted and Bernard's median ranks
/// F_i = (i - 0.3) / (n + 0.4): the usual Weibull-plot regression (ISO 20501 / ASTM C1239
/// give maximum likelihood as the reference; the regression is what a Weibull plot shows).
struct WeibullFit {
  double modulus = 0.0;     ///< m
  double scale = 0.0;       ///< s0, in the strengths' unit
  double r_squared = 0.0;   ///< of the regression line
  std::vector<double> sorted, ln_strength, ln_ln;  ///< the Weibull plot's points
};
/// Throws SweepError for fewer than 3 strengths, non-positive ones, or all equal.
WeibullFit fit_weibull(std::vector<double> strengths);

/// Strength against specimen size from a sweep over a size and a seed: per size the runs'
/// mean, standard deviation and (with 3 or more) Weibull fit; the exponent k of the power law
/// mean = A size^-k (least squares on the logarithms); and the Weibull modulus of all runs
/// pooled, each strength divided by its size's mean (the sizes' scatter on one plot).
/// Weibull's weakest link predicts k = d / m for an effective volume that grows as size^d
/// (d = 2 for a disc or plate of fixed thickness whose diameter is swept).
struct SizeGroup {
  double size = 0.0;
  std::vector<double> strengths;
  double mean = 0.0, stddev = 0.0;
  std::optional<WeibullFit> weibull;
};
struct SizeEffect {
  std::vector<SizeGroup> groups;  ///< by increasing size
  double exponent = 0.0;          ///< k of mean = A size^-k
  double prefactor = 0.0;         ///< A
  std::optional<WeibullFit> pooled;
};
/// Throws SweepError with fewer than two sizes or a non-positive size or strength.
SizeEffect fit_size_effect(const std::vector<std::pair<double, double>>& size_strength);

/// The plotting position (median rank) of the i-th of n sorted values, i from 1.
double median_rank(std::size_t i, std::size_t n);

}  // namespace cleave::io

#pragma once
/// \file
/// A parsed Scenario written back as a scenario file: the scenario as run, with every
/// default filled in, in metres (`length_unit = "m"`), so that `parse_scenario` reads it
/// back as an equal Scenario. A result folder keeps it as `scenario_as_run.toml`.

#include <string>
#include <vector>

#include "io/scenario.hpp"

namespace cleave::io {

/// The name of the scenario as run in a result folder.
constexpr const char* kScenarioAsRunName = "scenario_as_run.toml";

/// TOML text that parse_scenario reads back as `s` (every key written, lengths in metres,
/// numbers with the digits that round-trip). The two fields that describe the original
/// file rather than the run, `source` and `length_unit`, and the positions of keys in it,
/// are not carried over.
std::string scenario_to_toml(const Scenario& s);

/// The fields in which two scenarios differ, as dotted keys ("dynamics.dt",
/// "wall[2].velocity"); empty when they are equal. Compares what a run depends on: every
/// field except `source`, `length_unit` and the source positions. Numbers must be equal
/// exactly, except unit directions (wall normals, u, load axes), which are normalised again
/// on reading and may move by a few ulp (within 4e-16).
std::vector<std::string> scenario_differences(const Scenario& a, const Scenario& b);

}  // namespace cleave::io

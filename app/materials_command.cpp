/// \file
/// `cleave materials`: the material library (io/material_library.hpp), listed, or one
/// preset shown with every property in the unit written and in SI, with its source.

#include <fmt/format.h>

#include "commands.hpp"
#include "io/material_library.hpp"
#include "io/scenario.hpp"

namespace cleave::app {

int materials_command(const MaterialsOptions& options) {
  try {
    if (!options.name.empty()) {
      const auto file = io::resolve_material(options.name, ".");
      if (!file) {
        fmt::print(stderr, "cleave materials: no material '{}' in {} (`cleave materials` lists them)\n",
                   options.name, io::materials_dir().string());
        return 2;
      }
      fmt::print("{}", io::describe_material(io::load_material(*file)));
      return 0;
    }
    const auto files = io::library_files();
    if (files.empty()) {
      fmt::print(stderr, "cleave materials: no *.toml in {} (set CLEAVE_MATERIALS_DIR)\n",
                 io::materials_dir().string());
      return 2;
    }
    fmt::print("{:<18} {:>9} {:>8} {:>6} {:>10} {:>10} {:>10} {:>9}  {}\n", "preset", "rho kg/m3",
               "E GPa", "nu", "sigma_t MPa", "sigma_f MPa", "K_Ic MPa√m", "grain um", "what");
    for (const auto& f : files) {
      const io::MaterialPreset m = io::load_material(f);
      const auto* grain = m.find("grain_size");
      fmt::print("{:<18} {:>9.0f} {:>8.0f} {:>6.3f} {:>11.0f} {:>11.0f} {:>10.2f} {:>9}  {}\n",
                 m.name, m.si("density"), m.si("young") / 1e9, m.si("poisson"),
                 m.si("tensile_strength") / 1e6, m.si("flexural_strength") / 1e6,
                 m.si("k_ic") / 1e6, grain ? fmt::format("{:g}", grain->value / 1e-6) : "-",
                 m.description);
    }
    fmt::print("({} presets in {}; `cleave materials NAME` shows one with its sources)\n",
               files.size(), io::materials_dir().string());
    return 0;
  } catch (const io::ScenarioError& e) {
    fmt::print(stderr, "cleave materials: {}\n", e.what());
    return 2;
  }
}

}  // namespace cleave::app

#pragma once
/// \file
/// Text for the TOML files cleave writes by hand (scenario_as_run.toml, calibration.toml).

#include <fmt/format.h>

#include <string>
#include <string_view>

namespace cleave::io {

/// A TOML basic string: quoted, with backslash, quote and control characters escaped.
inline std::string toml_basic_string(std::string_view s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          out += fmt::format("\\u{:04X}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

}  // namespace cleave::io

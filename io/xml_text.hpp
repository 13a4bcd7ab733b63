#pragma once
/// \file
/// Text for the XML files cleave writes by hand (ParaView .vtp/.pvd, SVG pictures).

#include <string>
#include <string_view>

namespace cleave::io {

/// Appends `text` with the XML special characters escaped, safe inside a quoted attribute.
/// Control characters other than tab and newline, which XML 1.0 forbids, become spaces.
inline void append_xml_escaped(std::string& out, std::string_view text) {
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') ? ' ' : c;
    }
  }
}

}  // namespace cleave::io

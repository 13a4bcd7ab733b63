#include "io/vtk_output.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <utility>

#include "io/xml_text.hpp"

// File layout (what tests/test_vtk_output.cpp reads back):
//  * One <Piece> of VTK XML PolyData, version 1.0, header_type UInt64. Every DataArray is
//    format="appended" and the <AppendedData encoding="raw"> block holds, for each array in
//    the order the XML names them, a UInt64 byte count followed by the values as raw
//    little-endian Float64 (positions, scalars, vectors) or Int64 (connectivity, offsets,
//    ids). It is what vtkXMLWriter writes with EncodeAppendedData off: 8 bytes per value
//    against ~20 for full-precision ASCII and ~11 for base64. The XML head is plain text; the
//    file as a whole is not well-formed XML because of the raw bytes, as with VTK's own files.
//  * Non-finite values (NaN, +-inf) in positions or fields are written as they are, and VTK
//    reads them back unchanged (the test checks this with VTK 9.1 where it is installed).
//  * Field names must be non-empty, free of control characters and distinct across the
//    scalars, vectors, ids and strings of one FieldSet; the index array's name ("body_index"
//    or BodyFrame::index_name, "link_index" for links) is reserved. Names are XML-escaped.
//  * String fields are DataArrays of type "String" written inline with format="ascii", as
//    vtkXMLWriter writes a vtkStringArray: each string as its bytes' decimal codes, ended by
//    a 0 (so any text, control characters included, survives).
//  * Bodies: points are every mesh's vertices in mesh order, cells are their faces as Polys.
//  * Links: VTK stores cell data in the order Verts, Lines, Strips, Polys, so the zero-length
//    links (Verts) come first, then the others (Lines), each group in input order; the fields
//    are permuted to match and "link_index" gives each cell's position in the input. Points
//    are listed cell by cell: one per vertex cell, then a then b for each line.

namespace cleave::io {

namespace {

namespace fs = std::filesystem;

static_assert(std::endian::native == std::endian::little,
              "the appended data is written as raw little-endian bytes");
static_assert(std::numeric_limits<double>::is_iec559 && sizeof(double) == 8);

[[noreturn]] void fail(const fs::path& file, const std::string& what) {
  throw std::runtime_error("VTK output '" + file.string() + "': " + what);
}

std::string errno_message(int err) {
  return std::generic_category().message(err);
}

template <class Int>
void append_int(std::string& out, Int value) {
  char buf[24];
  const auto res = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, res.ptr);
}


/// True if `text` has a C0 control character or DEL. XML 1.0 cannot carry most of them even
/// escaped, and tab or newline in a name would be normalised away by XML parsers.
bool has_control_char(std::string_view text) {
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) return true;
  }
  return false;
}

/// A file written as `<file>.tmp` and renamed over `file` by commit(), so readers see either
/// the old file or the complete new one. The temporary is removed if commit() is not reached.
class AtomicFile {
 public:
  explicit AtomicFile(const fs::path& file) : file_(file), tmp_(file.string() + ".tmp") {
    file_handle_ = std::fopen(tmp_.c_str(), "wb");
    if (file_handle_ == nullptr) {
      const int err = errno;
      fail(file_, "cannot create '" + tmp_.string() + "': " + errno_message(err));
    }
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (file_handle_ != nullptr) std::fclose(file_handle_);
    if (!committed_) {
      std::error_code ec;
      fs::remove(tmp_, ec);
    }
  }

  void write(const void* data, std::size_t bytes) {
    if (bytes != 0 && std::fwrite(data, 1, bytes, file_handle_) != bytes) {
      const int err = errno;
      fail(file_, "cannot write '" + tmp_.string() + "': " + errno_message(err));
    }
  }
  void write(std::string_view text) { write(text.data(), text.size()); }

  void commit() {
    std::FILE* f = std::exchange(file_handle_, nullptr);
    if (std::fclose(f) != 0) {
      const int err = errno;
      fail(file_, "cannot finish '" + tmp_.string() + "': " + errno_message(err));
    }
    std::error_code ec;
    fs::rename(tmp_, file_, ec);
    if (ec) fail(file_, "cannot rename '" + tmp_.string() + "' into place: " + ec.message());
    committed_ = true;
  }

 private:
  fs::path file_;
  fs::path tmp_;
  std::FILE* file_handle_ = nullptr;
  bool committed_ = false;
};

/// Element type of a DataArray; the numbers are 8 bytes wide, strings are written inline.
enum class ValueType { float64, int64, string };

/// One DataArray of the appended block: `fill` writes its `values` 8-byte numbers (tuples
/// times components) to the buffer it is given.
struct Array {
  std::string name;
  ValueType type = ValueType::float64;
  int components = 1;
  std::size_t values = 0;
  std::function<void(char*)> fill;
  std::string ascii;  ///< a string array's inline text (ValueType::string)
};

/// A cell section of PolyData ("Verts", "Lines" or "Polys"): its cell count and its
/// connectivity and offsets arrays.
struct CellSection {
  const char* tag;
  std::size_t cells;
  Array connectivity;
  Array offsets;
};

/// Everything one PolyData piece holds.
struct Piece {
  std::size_t points = 0;
  std::vector<Array> cell_data;
  std::string active_scalars;  ///< the cell data's "Scalars" attribute, when not empty
  Array point_coords;
  std::vector<CellSection> sections;
};

inline void put(char* out, double v) {
  std::memcpy(out, &v, sizeof v);
}
inline void put(char* out, std::int64_t v) {
  std::memcpy(out, &v, sizeof v);
}

/// Writes `piece` as a .vtp with raw appended data; the arrays are filled one at a time into
/// one reused buffer, so the peak memory is the largest array, not the file.
void write_piece(const fs::path& file, const Piece& piece) {
  std::string xml;
  xml.reserve(4096);
  std::vector<const Array*> order;
  std::uint64_t offset = 0;
  auto data_array = [&](const Array& a) {
    xml += "        <DataArray type=\"";
    if (a.type == ValueType::string) {
      xml += "String\" Name=\"";
      append_xml_escaped(xml, a.name);
      xml += "\" NumberOfComponents=\"1\" NumberOfTuples=\"";
      append_int(xml, a.values);
      xml += "\" format=\"ascii\">\n";
      xml += a.ascii;
      xml += "\n        </DataArray>\n";
      return;
    }
    xml += a.type == ValueType::float64 ? "Float64" : "Int64";
    xml += "\" Name=\"";
    append_xml_escaped(xml, a.name);
    xml += "\" NumberOfComponents=\"";
    append_int(xml, a.components);
    xml += "\" format=\"appended\" offset=\"";
    append_int(xml, offset);
    xml += "\"/>\n";
    offset += sizeof(std::uint64_t) + 8 * static_cast<std::uint64_t>(a.values);
    order.push_back(&a);
  };
  auto count_of = [&](std::string_view tag) -> std::size_t {
    for (const auto& s : piece.sections) {
      if (tag == s.tag) return s.cells;
    }
    return 0;
  };

  xml += "<?xml version=\"1.0\"?>\n";
  xml +=
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n";
  xml += "  <PolyData>\n    <Piece NumberOfPoints=\"";
  append_int(xml, piece.points);
  for (const char* tag : {"Verts", "Lines", "Strips", "Polys"}) {
    xml += "\" NumberOf";
    xml += tag;
    xml += "=\"";
    append_int(xml, count_of(tag));
  }
  xml += "\">\n      <CellData";
  if (!piece.active_scalars.empty()) {
    xml += " Scalars=\"";
    append_xml_escaped(xml, piece.active_scalars);
    xml += "\"";
  }
  xml += ">\n";
  for (const auto& a : piece.cell_data) data_array(a);
  xml += "      </CellData>\n      <Points>\n";
  data_array(piece.point_coords);
  xml += "      </Points>\n";
  for (const auto& s : piece.sections) {
    xml += "      <";
    xml += s.tag;
    xml += ">\n";
    data_array(s.connectivity);
    data_array(s.offsets);
    xml += "      </";
    xml += s.tag;
    xml += ">\n";
  }
  xml += "    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";

  AtomicFile out(file);
  out.write(xml);
  std::size_t capacity = 0;
  std::unique_ptr<char[]> buffer;
  for (const Array* a : order) {
    const std::uint64_t bytes = 8 * static_cast<std::uint64_t>(a->values);
    const std::size_t total = sizeof bytes + bytes;
    if (total > capacity) {
      buffer = std::make_unique_for_overwrite<char[]>(total);
      capacity = total;
    }
    std::memcpy(buffer.get(), &bytes, sizeof bytes);
    if (bytes != 0) a->fill(buffer.get() + sizeof bytes);
    out.write(buffer.get(), total);
  }
  out.write("\n  </AppendedData>\n</VTKFile>\n");
  out.commit();
}

/// Checks a user field name: non-empty, no control characters, not already used.
void check_name(const fs::path& file, const std::string& name, std::set<std::string>& used) {
  if (name.empty()) fail(file, "a field has an empty name");
  if (has_control_char(name))
    fail(file, "field '" + name + "' has a control character in its name");
  if (!used.insert(name).second) {
    fail(file, "field name '" + name + "' is used twice (or is reserved by the writer)");
  }
}

template <class T>
void check_length(const fs::path& file, const std::string& name, const std::vector<T>& values,
                  std::size_t items, const char* item_word) {
  if (values.size() != items) {
    fail(file, "field '" + name + "' has " + std::to_string(values.size()) + " values for " +
                   std::to_string(items) + " " + item_word);
  }
}

/// Validates `fields` against `items` and appends one cell-data array per field, cell `c`
/// taking the value of item `cell_item[c]`. The arrays refer to `fields` and `cell_item`.
void add_fields(const fs::path& file, const FieldSet& fields, std::size_t items,
                const char* item_word, const std::string& reserved,
                const std::vector<std::size_t>& cell_item, std::vector<Array>& out) {
  std::set<std::string> used{reserved};
  const std::size_t cells = cell_item.size();
  for (const auto& field : fields.scalars) {
    const auto& name = field.first;  // not a structured binding: clang < 16 cannot capture those
    const auto& values = field.second;
    check_name(file, name, used);
    check_length(file, name, values, items, item_word);
    out.push_back({name, ValueType::float64, 1, cells, [&values, &cell_item](char* p) {
                     for (std::size_t c = 0; c < cell_item.size(); ++c) {
                       put(p + 8 * c, values[cell_item[c]]);
                     }
                   }});
  }
  for (const auto& field : fields.vectors) {
    const auto& name = field.first;  // not a structured binding: clang < 16 cannot capture those
    const auto& values = field.second;
    check_name(file, name, used);
    check_length(file, name, values, items, item_word);
    out.push_back({name, ValueType::float64, 3, 3 * cells, [&values, &cell_item](char* p) {
                     for (std::size_t c = 0; c < cell_item.size(); ++c) {
                       std::memcpy(p + 24 * c, values[cell_item[c]].data(), 24);
                     }
                   }});
  }
  for (const auto& field : fields.ids) {
    const auto& name = field.first;  // not a structured binding: clang < 16 cannot capture those
    const auto& values = field.second;
    check_name(file, name, used);
    check_length(file, name, values, items, item_word);
    out.push_back({name, ValueType::int64, 1, cells, [&values, &cell_item](char* p) {
                     for (std::size_t c = 0; c < cell_item.size(); ++c) {
                       put(p + 8 * c, static_cast<std::int64_t>(values[cell_item[c]]));
                     }
                   }});
  }
  for (const auto& [name, values] : fields.strings) {
    check_name(file, name, used);
    check_length(file, name, values, items, item_word);
    Array a{name, ValueType::string, 1, cells, {}, {}};
    a.ascii.reserve(cells * 16);
    for (std::size_t c = 0; c < cells; ++c) {
      a.ascii += c % 8 == 0 ? (c == 0 ? "          " : "\n          ") : " ";
      for (const char ch : values[cell_item[c]]) {
        append_int(a.ascii, static_cast<int>(static_cast<unsigned char>(ch)));
        a.ascii += ' ';
      }
      a.ascii += '0';
    }
    out.push_back(std::move(a));
  }
}

/// The index array the writer adds: cell `c` gets `cell_item[c]`.
Array index_array(const std::string& name, const std::vector<std::size_t>& cell_item) {
  return {name, ValueType::int64, 1, cell_item.size(), [&cell_item](char* p) {
            for (std::size_t c = 0; c < cell_item.size(); ++c) {
              put(p + 8 * c, static_cast<std::int64_t>(cell_item[c]));
            }
          }};
}

/// Coordinates of a sequence of points given by `point(i)` for i < n.
template <class PointAt>
Array coords_array(std::size_t n, PointAt point) {
  return {"Points", ValueType::float64, 3, 3 * n, [n, point](char* p) {
            for (std::size_t i = 0; i < n; ++i) std::memcpy(p + 24 * i, point(i).data(), 24);
          }};
}

/// Connectivity and offsets of `cells` cells of `size` points each, numbered from `first`.
CellSection uniform_section(const char* tag, std::size_t cells, std::size_t size,
                            std::size_t first) {
  const std::size_t corners = cells * size;
  return {tag, cells,
          Array{"connectivity", ValueType::int64, 1, corners,
                [corners, first](char* p) {
                  for (std::size_t i = 0; i < corners; ++i) {
                    put(p + 8 * i, static_cast<std::int64_t>(first + i));
                  }
                }},
          Array{"offsets", ValueType::int64, 1, cells, [cells, size](char* p) {
                  for (std::size_t c = 0; c < cells; ++c) {
                    put(p + 8 * c, static_cast<std::int64_t>((c + 1) * size));
                  }
                }}};
}

}  // namespace

void write_vtp(const fs::path& file, const BodyFrame& frame) {
  const auto& meshes = frame.meshes;
  std::size_t points = 0;
  std::size_t corners = 0;
  std::vector<std::size_t> cell_item;
  for (std::size_t b = 0; b < meshes.size(); ++b) {
    const auto& m = meshes[b];
    const auto n = static_cast<long long>(m.vertices.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
      const auto& face = m.faces[f];
      const std::string where =
          "body " + std::to_string(b) + " (mesh '" + m.name + "') face " + std::to_string(f);
      if (face.size() < 3) {
        fail(file, where + " has " + std::to_string(face.size()) + " vertices (need 3 or more)");
      }
      for (int v : face) {
        if (v < 0 || v >= n) {
          fail(file, where + " refers to vertex " + std::to_string(v) + " of " + std::to_string(n));
        }
      }
      corners += face.size();
    }
    points += m.vertices.size();
    cell_item.insert(cell_item.end(), m.faces.size(), b);
  }

  Piece piece;
  piece.points = points;
  if (frame.index_name.empty() || has_control_char(frame.index_name)) {
    fail(file,
         "the index array's name '" + frame.index_name + "' is empty or has a control character");
  }
  piece.cell_data.push_back(index_array(frame.index_name, cell_item));
  add_fields(file, frame.body_fields, meshes.size(), "bodies", frame.index_name, cell_item,
             piece.cell_data);
  if (!frame.active_scalars.empty()) {
    const bool known = std::any_of(piece.cell_data.begin(), piece.cell_data.end(),
                                   [&](const Array& a) { return a.name == frame.active_scalars; });
    if (!known) fail(file, "the active scalars '" + frame.active_scalars + "' are no field");
    piece.active_scalars = frame.active_scalars;
  }
  piece.point_coords = {"Points", ValueType::float64, 3, 3 * points, [&meshes](char* p) {
                          for (const auto& m : meshes) {
                            for (const auto& v : m.vertices) {
                              std::memcpy(p, v.data(), 24);
                              p += 24;
                            }
                          }
                        }};
  const std::size_t polys = cell_item.size();
  Array connectivity{"connectivity", ValueType::int64, 1, corners, [&meshes](char* p) {
                       std::int64_t base = 0;
                       for (const auto& m : meshes) {
                         for (const auto& face : m.faces) {
                           for (int v : face) {
                             put(p, base + v);
                             p += 8;
                           }
                         }
                         base += static_cast<std::int64_t>(m.vertices.size());
                       }
                     }};
  Array offsets{"offsets", ValueType::int64, 1, polys, [&meshes](char* p) {
                  std::int64_t end = 0;
                  for (const auto& m : meshes) {
                    for (const auto& face : m.faces) {
                      end += static_cast<std::int64_t>(face.size());
                      put(p, end);
                      p += 8;
                    }
                  }
                }};
  piece.sections.push_back({"Polys", polys, std::move(connectivity), std::move(offsets)});
  write_piece(file, piece);
}

void write_vtp(const fs::path& file, const LinkFrame& frame) {
  const auto& a = frame.a;
  const auto& b = frame.b;
  if (a.size() != b.size()) {
    fail(file, "links have " + std::to_string(a.size()) + " start points but " +
                   std::to_string(b.size()) + " end points");
  }
  std::vector<std::size_t> cell_item;
  cell_item.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] == b[i]) cell_item.push_back(i);
  }
  const std::size_t verts = cell_item.size();
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] != b[i]) cell_item.push_back(i);
  }
  const std::size_t lines = cell_item.size() - verts;

  Piece piece;
  piece.points = verts + 2 * lines;
  piece.cell_data.push_back(index_array("link_index", cell_item));
  add_fields(file, frame.fields, a.size(), "links", "link_index", cell_item, piece.cell_data);
  piece.point_coords = coords_array(piece.points, [&a, &b, &cell_item, verts](std::size_t i) {
    if (i < verts) return a[cell_item[i]];
    const std::size_t k = i - verts;
    const std::size_t link = cell_item[verts + k / 2];
    return k % 2 == 0 ? a[link] : b[link];
  });
  piece.sections.push_back(uniform_section("Verts", verts, 1, 0));
  piece.sections.push_back(uniform_section("Lines", lines, 2, verts));
  write_piece(file, piece);
}

PvdSeries::PvdSeries(fs::path pvd_file) : file_(std::move(pvd_file)) {}

void PvdSeries::add(double time, const fs::path& relative_file, int part) {
  if (!std::isfinite(time)) {
    fail(file_,
         "time " + std::to_string(time) + " for '" + relative_file.string() + "' is not finite");
  }
  std::string name = relative_file.generic_string();
  if (name.empty() || has_control_char(name)) {
    fail(file_, "dataset file name '" + name + "' is empty or has a control character");
  }
  // A second dataset at the same time and part (a frame rewritten at the same step) takes
  // the last entry's place: ParaView would otherwise show both at once.
  std::optional<Entry> replaced;
  if (!entries_.empty() && entries_.back().time == time && entries_.back().part == part) {
    replaced = entries_.back();
    entries_.pop_back();
  }
  entries_.push_back({time, std::move(name), part});

  std::string xml;
  xml += "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  xml += "  <Collection>\n";
  for (const auto& e : entries_) {
    char buf[32];
    const auto res = std::to_chars(buf, buf + sizeof buf, e.time);
    xml += "    <DataSet timestep=\"";
    xml.append(buf, res.ptr);
    xml += "\" group=\"\" part=\"";
    append_int(xml, e.part);
    xml += "\" file=\"";
    append_xml_escaped(xml, e.file);
    xml += "\"/>\n";
  }
  xml += "  </Collection>\n</VTKFile>\n";
  try {
    AtomicFile out(file_);
    out.write(xml);
    out.commit();
  } catch (...) {
    entries_.pop_back();
    if (replaced) entries_.push_back(std::move(*replaced));
    throw;
  }
}

}  // namespace cleave::io

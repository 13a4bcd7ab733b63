// Reads back what io/vtk_output writes, with a minimal reader written here: the XML head is
// scanned into a flat list of tags, the raw appended arrays are decoded by their offsets, and
// everything is compared with hand-built meshes, links and fields. Where a Python with VTK is
// installed (Debian: python3-vtk9), VTK's own reader is run on the same files as well.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/polygon_mesh.hpp"
#include "io/vtk_output.hpp"

namespace {

namespace fs = std::filesystem;
using cleave::geometry::PolygonMesh;
using cleave::io::BodyFrame;
using cleave::io::LinkFrame;
using cleave::io::PvdSeries;
using cleave::io::write_vtp;
using Eigen::Vector3d;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// A fresh folder for one test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("cleave_vtk_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  [[nodiscard]] const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("test cannot open " + file.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// ---------------------------------------------------------------------------------------
// A minimal XML tag scanner: enough for the files under test, strict about what it accepts.

struct Tag {
  enum Kind { declaration, open, close, empty } kind = open;
  std::string name;
  std::map<std::string, std::string> attrs;
};

std::string unescape(std::string_view s) {
  static const std::map<std::string, char> entities = {
      {"amp", '&'}, {"lt", '<'}, {"gt", '>'}, {"quot", '"'}, {"apos", '\''}};
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '<') throw std::runtime_error("raw '<' in an attribute value");
    if (s[i] != '&') {
      out += s[i];
      continue;
    }
    const auto semi = s.find(';', i);
    if (semi == std::string_view::npos) throw std::runtime_error("unterminated entity");
    const auto it = entities.find(std::string(s.substr(i + 1, semi - i - 1)));
    if (it == entities.end()) throw std::runtime_error("unknown entity");
    out += it->second;
    i = semi;
  }
  return out;
}

bool is_space(char c) {
  return c == ' ' || c == '\n' || c == '\t' || c == '\r';
}

/// Tags of `xml` in document order; text between tags must be whitespace.
std::vector<Tag> scan_tags(std::string_view xml) {
  std::vector<Tag> tags;
  std::size_t i = 0;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error("XML scan at byte " + std::to_string(i) + ": " + what);
  };
  auto name_end = [&](std::size_t from) {
    std::size_t j = from;
    while (j < xml.size() && !is_space(xml[j]) && xml[j] != '>' && xml[j] != '/' && xml[j] != '=') {
      ++j;
    }
    return j;
  };
  while (i < xml.size()) {
    if (is_space(xml[i])) {
      ++i;
      continue;
    }
    if (xml[i] != '<') fail("text outside tags");
    Tag tag;
    if (xml.substr(i, 2) == "<?") {
      const auto end = xml.find("?>", i);
      if (end == std::string_view::npos) fail("unterminated declaration");
      tag.kind = Tag::declaration;
      tag.name = std::string(xml.substr(i + 2, name_end(i + 2) - i - 2));
      tags.push_back(tag);
      i = end + 2;
      continue;
    }
    if (xml.substr(i, 2) == "</") {
      tag.kind = Tag::close;
      const auto e = name_end(i + 2);
      tag.name = std::string(xml.substr(i + 2, e - i - 2));
      i = e;
      while (i < xml.size() && is_space(xml[i])) ++i;
      if (i >= xml.size() || xml[i] != '>') fail("bad closing tag");
      ++i;
      tags.push_back(tag);
      continue;
    }
    std::size_t e = name_end(i + 1);
    tag.name = std::string(xml.substr(i + 1, e - i - 1));
    if (tag.name.empty()) fail("tag without a name");
    i = e;
    while (true) {
      while (i < xml.size() && is_space(xml[i])) ++i;
      if (i >= xml.size()) fail("unterminated tag");
      if (xml.substr(i, 2) == "/>") {
        tag.kind = Tag::empty;
        i += 2;
        break;
      }
      if (xml[i] == '>') {
        tag.kind = Tag::open;
        ++i;
        break;
      }
      e = name_end(i);
      const std::string attr(xml.substr(i, e - i));
      if (attr.empty() || e + 1 >= xml.size() || xml[e] != '=' || xml[e + 1] != '"') {
        fail("bad attribute");
      }
      const auto close = xml.find('"', e + 2);
      if (close == std::string_view::npos) fail("unterminated attribute value");
      if (!tag.attrs.emplace(attr, unescape(xml.substr(e + 2, close - e - 2))).second) {
        fail("attribute '" + attr + "' given twice");
      }
      i = close + 1;
      if (i < xml.size() && !is_space(xml[i]) && xml[i] != '>' && xml[i] != '/') {
        fail("no space after an attribute");
      }
    }
    tags.push_back(tag);
  }
  return tags;
}

/// Empty when the tags form one properly nested element (after an optional declaration);
/// otherwise what is wrong.
std::string nesting_error(const std::vector<Tag>& tags) {
  std::vector<std::string> stack;
  int roots = 0;
  for (std::size_t k = 0; k < tags.size(); ++k) {
    const Tag& t = tags[k];
    if (t.kind == Tag::declaration) {
      if (k != 0 || t.name != "xml") return "declaration not first";
      continue;
    }
    if (stack.empty()) {
      if (t.kind == Tag::close) return "stray closing tag " + t.name;
      ++roots;
    }
    if (t.kind == Tag::open) stack.push_back(t.name);
    if (t.kind == Tag::close) {
      if (stack.back() != t.name) return "</" + t.name + "> closes <" + stack.back() + ">";
      stack.pop_back();
    }
  }
  if (!stack.empty()) return "<" + stack.back() + "> never closed";
  if (roots != 1) return std::to_string(roots) + " root elements";
  return "";
}

// ---------------------------------------------------------------------------------------
// A minimal .vtp reader for raw appended data with UInt64 block headers.

struct DataArray {
  std::string type;
  int components = 1;
  std::uint64_t offset = 0;
  std::vector<double> f64;
  std::vector<std::int64_t> i64;
  [[nodiscard]] std::size_t values() const { return type == "Float64" ? f64.size() : i64.size(); }
};

struct Vtp {
  std::vector<Tag> tags;                           ///< whole document, data block left out
  std::map<std::string, std::string> root, piece;  ///< attributes of <VTKFile>, <Piece>
  std::string encoding;                            ///< of <AppendedData>
  std::map<std::string, DataArray> arrays;         ///< by "Parent/Name", e.g. "Polys/offsets"
  std::vector<std::string> cell_data;              ///< cell array names in file order

  [[nodiscard]] const DataArray& at(const std::string& key) const {
    const auto it = arrays.find(key);
    if (it == arrays.end()) throw std::runtime_error("no array " + key);
    return it->second;
  }
  [[nodiscard]] std::vector<double> f64(const std::string& key) const {
    const auto& a = at(key);
    if (a.type != "Float64") throw std::runtime_error(key + " is " + a.type);
    return a.f64;
  }
  [[nodiscard]] std::vector<std::int64_t> i64(const std::string& key) const {
    const auto& a = at(key);
    if (a.type != "Int64") throw std::runtime_error(key + " is " + a.type);
    return a.i64;
  }
  [[nodiscard]] std::size_t count(const std::string& attr) const {
    const auto it = piece.find(attr);
    return it == piece.end() ? 0 : std::stoul(it->second);
  }
};

Vtp read_vtp(const fs::path& file) {
  const std::string bytes = read_bytes(file);
  const std::string marker = "<AppendedData encoding=\"raw\">";
  const auto m = bytes.find(marker);
  if (m == std::string::npos) throw std::runtime_error("no raw AppendedData element");
  std::size_t underscore = m + marker.size();
  while (underscore < bytes.size() && is_space(bytes[underscore])) ++underscore;
  if (underscore >= bytes.size() || bytes[underscore] != '_') {
    throw std::runtime_error("appended data does not start with '_'");
  }
  Vtp vtp;
  vtp.tags = scan_tags(std::string_view(bytes).substr(0, underscore));
  std::vector<std::string> parents;
  std::vector<DataArray*> in_file_order;
  for (const Tag& t : vtp.tags) {
    if (t.kind == Tag::close) parents.pop_back();
    if (t.kind != Tag::open && t.kind != Tag::empty) continue;
    if (t.kind == Tag::open) parents.push_back(t.name);
    if (t.name == "VTKFile") vtp.root = t.attrs;
    if (t.name == "Piece") vtp.piece = t.attrs;
    if (t.name == "AppendedData") vtp.encoding = t.attrs.at("encoding");
    if (t.name != "DataArray") continue;
    if (t.kind != Tag::empty) throw std::runtime_error("DataArray with content");
    if (parents.empty()) throw std::runtime_error("DataArray outside any element");
    if (t.attrs.at("format") != "appended") throw std::runtime_error("not appended");
    const std::string key = parents.back() + "/" + t.attrs.at("Name");
    DataArray a;
    a.type = t.attrs.at("type");
    a.components =
        t.attrs.count("NumberOfComponents") ? std::stoi(t.attrs.at("NumberOfComponents")) : 1;
    a.offset = std::stoull(t.attrs.at("offset"));
    if (!vtp.arrays.emplace(key, a).second) throw std::runtime_error("duplicate array " + key);
    in_file_order.push_back(&vtp.arrays.at(key));
    if (parents.back() == "CellData") vtp.cell_data.push_back(t.attrs.at("Name"));
  }
  // The blocks must tile the data region: sorted by offset, each starts where the last ended.
  std::sort(in_file_order.begin(), in_file_order.end(),
            [](const DataArray* x, const DataArray* y) { return x->offset < y->offset; });
  const std::size_t data = underscore + 1;
  std::uint64_t expected_offset = 0;
  for (DataArray* a : in_file_order) {
    if (a->offset != expected_offset) throw std::runtime_error("gap or overlap in data");
    std::uint64_t n = 0;
    if (data + a->offset + 8 > bytes.size()) throw std::runtime_error("block header past end");
    std::memcpy(&n, bytes.data() + data + a->offset, 8);
    if (n % 8 != 0 || data + a->offset + 8 + n > bytes.size()) {
      throw std::runtime_error("bad block size");
    }
    const char* p = bytes.data() + data + a->offset + 8;
    for (std::uint64_t k = 0; k < n / 8; ++k) {
      if (a->type == "Float64") {
        double v;
        std::memcpy(&v, p + 8 * k, 8);
        a->f64.push_back(v);
      } else if (a->type == "Int64") {
        std::int64_t v;
        std::memcpy(&v, p + 8 * k, 8);
        a->i64.push_back(v);
      } else {
        throw std::runtime_error("unexpected type " + a->type);
      }
    }
    expected_offset = a->offset + 8 + n;
  }
  const auto tail = scan_tags(std::string_view(bytes).substr(data + expected_offset));
  vtp.tags.insert(vtp.tags.end(), tail.begin(), tail.end());
  return vtp;
}

/// Point `k` of the "Points" array.
Vector3d point(const Vtp& vtp, std::int64_t k) {
  const auto& p = vtp.at("Points/Points").f64;
  return {p.at(3 * k), p.at(3 * k + 1), p.at(3 * k + 2)};
}

/// The points of cell `c` of a section ("Polys", "Lines", "Verts") through its
/// connectivity and offsets.
std::vector<Vector3d> cell_points(const Vtp& vtp, const std::string& section, std::size_t c) {
  const auto conn = vtp.i64(section + "/connectivity");
  const auto offs = vtp.i64(section + "/offsets");
  const std::int64_t begin = c == 0 ? 0 : offs.at(c - 1);
  std::vector<Vector3d> out;
  for (std::int64_t k = begin; k < offs.at(c); ++k) out.push_back(point(vtp, conn.at(k)));
  return out;
}

/// Equal as bit-exact doubles, NaN equal to NaN.
bool same(double x, double y) {
  return (std::isnan(x) && std::isnan(y)) || x == y;
}

void expect_same(const std::vector<double>& got, const std::vector<double>& want,
                 const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_TRUE(same(got[i], want[i]))
        << what << "[" << i << "] = " << got[i] << ", want " << want[i];
  }
}

// ---------------------------------------------------------------------------------------
// Hand-built frames.

PolygonMesh tetrahedron() {
  PolygonMesh m;
  m.name = "tet";
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

/// Unit cube with its lowest corner at (2, 0, 0).
PolygonMesh cube() {
  PolygonMesh m;
  m.name = "cube";
  m.vertices = {{2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {2, 1, 0},
                {2, 0, 1}, {3, 0, 1}, {3, 1, 1}, {2, 1, 1}};
  m.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  return m;
}

const std::string kOddName = "r&d <\"x\"> 'y'";

BodyFrame sample_bodies() {
  BodyFrame f;
  f.meshes = {tetrahedron(), cube()};
  f.body_fields.scalars["mass"] = {1.5, 2.5};
  f.body_fields.scalars["strain"] = {kNaN, -kInf};
  f.body_fields.scalars[kOddName] = {7, 8};
  f.body_fields.vectors["velocity"] = {Vector3d(1, -2, 3), Vector3d(0.25, 5, -6)};
  f.body_fields.ids["grain"] = {17, -42};
  return f;
}

/// Links 1 and 3 have zero length (vertices); 4 is very short but not zero (a line).
LinkFrame sample_links() {
  LinkFrame f;
  f.a = {{0, 0, 0}, {2, 2, 2}, {0, 1, 0}, {-1, -1, -1}, {1, 1, 1}};
  f.b = {{1, 0, 0}, {2, 2, 2}, {0, 1, 5}, {-1, -1, -1}, {1, 1, 1 + 1e-12}};
  f.fields.scalars["force"] = {10, 11, 12, 13, 14};
  f.fields.vectors["normal"] = {Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(0, 0, 1),
                                Vector3d(-1, 0, 0), Vector3d(0, -1, 0)};
  f.fields.ids["contact_id"] = {100, 101, 102, 103, 104};
  return f;
}

void expect_vtp_header(const Vtp& vtp) {
  EXPECT_EQ(nesting_error(vtp.tags), "");
  ASSERT_FALSE(vtp.tags.empty());
  EXPECT_EQ(vtp.tags.front().kind, Tag::declaration);
  EXPECT_EQ(vtp.root.at("type"), "PolyData");
  EXPECT_EQ(vtp.root.at("version"), "1.0");
  EXPECT_EQ(vtp.root.at("byte_order"), "LittleEndian");
  EXPECT_EQ(vtp.root.at("header_type"), "UInt64");
  EXPECT_EQ(vtp.encoding, "raw");
  EXPECT_EQ(vtp.count("NumberOfStrips"), 0u);
}

/// Every CellData array has one tuple per cell; Points one per point.
void expect_consistent_counts(const Vtp& vtp) {
  const std::size_t cells = vtp.count("NumberOfVerts") + vtp.count("NumberOfLines") +
                            vtp.count("NumberOfStrips") + vtp.count("NumberOfPolys");
  for (const auto& name : vtp.cell_data) {
    const auto& a = vtp.at("CellData/" + name);
    EXPECT_EQ(a.values(), cells * a.components) << name;
  }
  const auto& pts = vtp.at("Points/Points");
  EXPECT_EQ(pts.components, 3);
  EXPECT_EQ(pts.values(), 3 * vtp.count("NumberOfPoints"));
}

// ---------------------------------------------------------------------------------------

TEST(VtkOutput, BodyFrameReadsBackAsTheHandBuiltMeshesAndFields) {
  TempDir dir;
  const BodyFrame frame = sample_bodies();
  ASSERT_TRUE(frame.meshes[0].is_closed_and_consistently_oriented());
  ASSERT_TRUE(frame.meshes[1].is_closed_and_consistently_oriented());
  const fs::path file = dir / "bodies.vtp";
  write_vtp(file, frame);
  EXPECT_FALSE(fs::exists(dir / "bodies.vtp.tmp"));
  const Vtp vtp = read_vtp(file);

  expect_vtp_header(vtp);
  expect_consistent_counts(vtp);
  EXPECT_EQ(vtp.count("NumberOfPoints"), 12u);
  EXPECT_EQ(vtp.count("NumberOfPolys"), 10u);
  EXPECT_EQ(vtp.count("NumberOfLines"), 0u);
  EXPECT_EQ(vtp.count("NumberOfVerts"), 0u);

  expect_same(vtp.f64("Points/Points"), {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1,   // tetrahedron
                                         2, 0, 0, 3, 0, 0, 3, 1, 0, 2, 1, 0,   // cube, bottom
                                         2, 0, 1, 3, 0, 1, 3, 1, 1, 2, 1, 1},  // cube, top
              "points");
  EXPECT_EQ(vtp.i64("Polys/connectivity"),
            (std::vector<std::int64_t>{0, 2, 1,  0, 1, 3, 0,  3,  2, 1, 2, 3,  // tetrahedron
                                       4, 7, 6,  5, 8, 9, 10, 11, 4, 5, 9, 8,  // cube
                                       5, 6, 10, 9, 6, 7, 11, 10, 7, 4, 8, 11}));
  EXPECT_EQ(vtp.i64("Polys/offsets"),
            (std::vector<std::int64_t>{3, 6, 9, 12, 16, 20, 24, 28, 32, 36}));

  const std::set<std::string> names(vtp.cell_data.begin(), vtp.cell_data.end());
  EXPECT_EQ(names,
            (std::set<std::string>{"body_index", "mass", "strain", "velocity", "grain", kOddName}));
  EXPECT_EQ(vtp.cell_data.size(), names.size());
  EXPECT_EQ(vtp.i64("CellData/body_index"),
            (std::vector<std::int64_t>{0, 0, 0, 0, 1, 1, 1, 1, 1, 1}));
  expect_same(vtp.f64("CellData/mass"), {1.5, 1.5, 1.5, 1.5, 2.5, 2.5, 2.5, 2.5, 2.5, 2.5}, "mass");
  expect_same(vtp.f64("CellData/strain"),
              {kNaN, kNaN, kNaN, kNaN, -kInf, -kInf, -kInf, -kInf, -kInf, -kInf}, "strain");
  expect_same(vtp.f64("CellData/" + kOddName), {7, 7, 7, 7, 8, 8, 8, 8, 8, 8}, "odd name");
  EXPECT_EQ(vtp.at("CellData/velocity").components, 3);
  expect_same(vtp.f64("CellData/velocity"),
              {1,    -2, 3,  1,    -2, 3,  1,    -2, 3,  1,    -2, 3,                // tetrahedron
               0.25, 5,  -6, 0.25, 5,  -6, 0.25, 5,  -6, 0.25, 5,  -6, 0.25, 5, -6,  // cube
               0.25, 5,  -6},
              "velocity");
  EXPECT_EQ(vtp.i64("CellData/grain"),
            (std::vector<std::int64_t>{17, 17, 17, 17, -42, -42, -42, -42, -42, -42}));
  EXPECT_EQ(vtp.at("CellData/mass").components, 1);
  EXPECT_EQ(vtp.at("CellData/grain").components, 1);
}

TEST(VtkOutput, LinkFramePutsZeroLengthLinksInVertsFirstAndReordersTheirFields) {
  TempDir dir;
  const LinkFrame frame = sample_links();
  const fs::path file = dir / "links.vtp";
  write_vtp(file, frame);
  const Vtp vtp = read_vtp(file);

  expect_vtp_header(vtp);
  expect_consistent_counts(vtp);
  EXPECT_EQ(vtp.count("NumberOfVerts"), 2u);
  EXPECT_EQ(vtp.count("NumberOfLines"), 3u);
  EXPECT_EQ(vtp.count("NumberOfPolys"), 0u);
  EXPECT_EQ(vtp.count("NumberOfPoints"), 8u);
  EXPECT_EQ(vtp.i64("Verts/offsets"), (std::vector<std::int64_t>{1, 2}));
  EXPECT_EQ(vtp.i64("Lines/offsets"), (std::vector<std::int64_t>{2, 4, 6}));

  // Cells in VTK's order: Verts (links 1, 3), then Lines (links 0, 2, 4).
  const std::vector<std::size_t> vert_links = {1, 3};
  const std::vector<std::size_t> line_links = {0, 2, 4};
  for (std::size_t k = 0; k < vert_links.size(); ++k) {
    const auto pts = cell_points(vtp, "Verts", k);
    ASSERT_EQ(pts.size(), 1u);
    EXPECT_EQ(pts[0], frame.a[vert_links[k]]) << "vertex cell " << k;
  }
  for (std::size_t k = 0; k < line_links.size(); ++k) {
    const auto pts = cell_points(vtp, "Lines", k);
    ASSERT_EQ(pts.size(), 2u);
    EXPECT_EQ(pts[0], frame.a[line_links[k]]) << "line cell " << k;
    EXPECT_EQ(pts[1], frame.b[line_links[k]]) << "line cell " << k;
  }
  EXPECT_EQ(vtp.i64("CellData/link_index"), (std::vector<std::int64_t>{1, 3, 0, 2, 4}));
  expect_same(vtp.f64("CellData/force"), {11, 13, 10, 12, 14}, "force");
  EXPECT_EQ(vtp.i64("CellData/contact_id"), (std::vector<std::int64_t>{101, 103, 100, 102, 104}));
  expect_same(vtp.f64("CellData/normal"), {0, 1, 0, -1, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, 0},
              "normal");
}

TEST(VtkOutput, EmptyFramesGiveEmptyButValidFiles) {
  TempDir dir;
  write_vtp(dir / "no_bodies.vtp", BodyFrame{});
  write_vtp(dir / "no_links.vtp", LinkFrame{});
  for (const char* name : {"no_bodies.vtp", "no_links.vtp"}) {
    SCOPED_TRACE(name);
    const Vtp vtp = read_vtp(dir / name);
    expect_vtp_header(vtp);
    expect_consistent_counts(vtp);
    EXPECT_EQ(vtp.count("NumberOfPoints"), 0u);
    EXPECT_EQ(vtp.count("NumberOfPolys") + vtp.count("NumberOfLines") + vtp.count("NumberOfVerts"),
              0u);
  }
}

/// Runs `write` expecting a std::runtime_error whose message contains every one of `words`.
template <class Write>
void expect_error_naming(Write write, const std::vector<std::string>& words) {
  try {
    write();
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    for (const auto& w : words) EXPECT_NE(what.find(w), std::string::npos) << what << " / " << w;
  }
}

TEST(VtkOutput, FieldLengthMismatchThrowsNamingFileAndFieldAndWritesNothing) {
  TempDir dir;
  const fs::path file = dir / "bad.vtp";
  {
    BodyFrame f = sample_bodies();
    f.body_fields.scalars["mass"].push_back(3.5);
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "mass"});
  }
  {
    BodyFrame f = sample_bodies();
    f.body_fields.vectors["velocity"].pop_back();
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "velocity"});
  }
  {
    BodyFrame f = sample_bodies();
    f.body_fields.ids["grain"].clear();
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "grain"});
  }
  {
    LinkFrame f = sample_links();
    f.fields.scalars["force"].pop_back();
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "force"});
  }
  {
    LinkFrame f = sample_links();
    f.fields.ids["contact_id"].push_back(7);
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "contact_id"});
  }
  {
    LinkFrame f = sample_links();
    f.b.pop_back();
    expect_error_naming([&] { write_vtp(file, f); }, {file.string()});
  }
  EXPECT_FALSE(fs::exists(file));
  EXPECT_FALSE(fs::exists(dir / "bad.vtp.tmp"));
}

TEST(VtkOutput, BadNamesAndBadFacesThrow) {
  TempDir dir;
  const fs::path file = dir / "bad.vtp";
  {
    BodyFrame f = sample_bodies();
    f.body_fields.ids["body_index"] = {5, 6};
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "body_index"});
  }
  {
    BodyFrame f = sample_bodies();
    f.body_fields.vectors["mass"] = {Vector3d::Zero(), Vector3d::Zero()};
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "mass"});
  }
  {
    LinkFrame f = sample_links();
    f.fields.scalars["bad\nname"] = {1, 2, 3, 4, 5};
    expect_error_naming([&] { write_vtp(file, f); }, {file.string()});
  }
  {
    BodyFrame f = sample_bodies();
    f.meshes[1].faces[2][1] = 8;
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "cube"});
  }
  {
    BodyFrame f = sample_bodies();
    f.meshes[0].faces[0].pop_back();
    expect_error_naming([&] { write_vtp(file, f); }, {file.string(), "tet"});
  }
  EXPECT_FALSE(fs::exists(file));
}

TEST(VtkOutput, MissingFolderThrowsNamingTheFile) {
  TempDir dir;
  const fs::path bodies = dir / "no_such_folder" / "bodies.vtp";
  const fs::path links = dir / "no_such_folder" / "links.vtp";
  const fs::path pvd = dir / "no_such_folder" / "run.pvd";
  expect_error_naming([&] { write_vtp(bodies, sample_bodies()); }, {bodies.string()});
  expect_error_naming([&] { write_vtp(links, sample_links()); }, {links.string()});
  PvdSeries series(pvd);
  expect_error_naming([&] { series.add(0.0, "bodies.vtp"); }, {pvd.string()});
  EXPECT_FALSE(fs::exists(dir / "no_such_folder"));
}

TEST(VtkOutput, RewritingAFileReplacesItWhole) {
  TempDir dir;
  const fs::path file = dir / "frame.vtp";
  write_vtp(file, sample_bodies());
  const std::string first = read_bytes(file);
  BodyFrame small;
  small.meshes = {tetrahedron()};
  write_vtp(file, small);
  EXPECT_LT(read_bytes(file).size(), first.size());
  EXPECT_EQ(read_vtp(file).count("NumberOfPolys"), 4u);
  EXPECT_FALSE(fs::exists(dir / "frame.vtp.tmp"));

  // A rejected frame leaves the previous file as it was.
  const std::string before = read_bytes(file);
  BodyFrame bad = sample_bodies();
  bad.body_fields.scalars["mass"].clear();
  EXPECT_THROW(write_vtp(file, bad), std::runtime_error);
  EXPECT_EQ(read_bytes(file), before);
}

TEST(VtkOutput, WritesGoThroughATemporaryFileNextToTheTarget) {
  TempDir dir;
  const fs::path file = dir / "frame.vtp";
  write_vtp(file, sample_links());
  const std::string before = read_bytes(file);
  // A folder squatting on "<file>.tmp" makes the write fail before the target is touched.
  fs::create_directory(dir / "frame.vtp.tmp");
  expect_error_naming([&] { write_vtp(file, sample_bodies()); }, {file.string(), ".tmp"});
  EXPECT_EQ(read_bytes(file), before);
  fs::create_directory(dir / "run.pvd.tmp");
  PvdSeries series(dir / "run.pvd");
  expect_error_naming([&] { series.add(0.0, "frame.vtp"); }, {(dir / "run.pvd").string()});
  EXPECT_FALSE(fs::exists(dir / "run.pvd"));
}

/// The DataSet entries of a .pvd, checked to be well formed with the expected root.
std::vector<std::map<std::string, std::string>> read_pvd(const fs::path& file) {
  const auto tags = scan_tags(read_bytes(file));
  EXPECT_EQ(nesting_error(tags), "");
  std::vector<std::map<std::string, std::string>> out;
  std::vector<std::string> parents;
  for (const auto& t : tags) {
    if (t.name == "VTKFile" && t.kind == Tag::open) {
      EXPECT_EQ(t.attrs.count("type") ? t.attrs.at("type") : "", "Collection");
    }
    if (t.kind == Tag::open) parents.push_back(t.name);
    if (t.kind == Tag::close) parents.pop_back();
    if (t.name == "DataSet") {
      EXPECT_EQ(t.kind, Tag::empty);
      EXPECT_EQ(parents, (std::vector<std::string>{"VTKFile", "Collection"}));
      out.push_back(t.attrs);
    }
  }
  return out;
}

TEST(VtkOutput, PvdListsEveryAddedFrameInOrder) {
  TempDir dir;
  const fs::path pvd = dir / "run.pvd";
  PvdSeries series(pvd);
  EXPECT_EQ(series.file(), pvd);
  struct Want {
    double time;
    std::string file;
    int part;
  };
  const std::vector<Want> adds = {{0.0, "frames/bodies_0.vtp", 0},
                                  {0.1, "frames/links_0.vtp", 1},
                                  {2.5e-7, "frames/bodies_1.vtp", 0},
                                  {1.0 / 3.0, "frames/a&b <1>.vtp", 1}};
  for (std::size_t n = 0; n < adds.size(); ++n) {
    series.add(adds[n].time, adds[n].file, adds[n].part);
    EXPECT_FALSE(fs::exists(dir / "run.pvd.tmp"));
    const auto entries = read_pvd(pvd);
    ASSERT_EQ(entries.size(), n + 1);
    for (std::size_t k = 0; k <= n; ++k) {
      EXPECT_EQ(std::stod(entries[k].at("timestep")), adds[k].time) << k;
      EXPECT_EQ(entries[k].at("file"), adds[k].file) << k;
      EXPECT_EQ(std::stoi(entries[k].at("part")), adds[k].part) << k;
    }
  }
  // A rejected entry changes nothing, and the series goes on.
  EXPECT_THROW(series.add(kNaN, "frames/nan.vtp"), std::runtime_error);
  EXPECT_EQ(read_pvd(pvd).size(), adds.size());
  series.add(5.0, "frames/last.vtp");
  const auto entries = read_pvd(pvd);
  ASSERT_EQ(entries.size(), adds.size() + 1);
  EXPECT_EQ(entries.back().at("file"), "frames/last.vtp");
  EXPECT_EQ(entries.back().at("part"), "0");
}

/// ParaView shows every dataset of one time and part at once: a frame written again at the
/// same time (the bond stage right after the first frame) replaces the entry, and a failed
/// replacement keeps the old one.
TEST(VtkOutput, PvdListsEachTimeAndPartOnce) {
  TempDir dir;
  const fs::path pvd = dir / "run.pvd";
  PvdSeries series(pvd);
  series.add(0.0, "frames/bodies_000000.vtp");
  series.add(0.0, "frames/cell_000000.vtp", 1);  // another part at the same time stays
  series.add(0.0, "frames/cell_again.vtp", 1);
  series.add(0.5, "frames/bodies_000001.vtp");
  series.add(0.5, "frames/bodies_again.vtp");
  auto entries = read_pvd(pvd);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[1].at("file"), "frames/cell_again.vtp");
  EXPECT_EQ(entries[2].at("file"), "frames/bodies_again.vtp");
  EXPECT_EQ(series.entries().size(), 3u);
  fs::create_directory(dir / "run.pvd.tmp");  // the next write fails
  EXPECT_THROW(series.add(0.5, "frames/lost.vtp"), std::runtime_error);
  ASSERT_EQ(series.entries().size(), 3u);
  EXPECT_EQ(series.entries().back().file, "frames/bodies_again.vtp");
}

TEST(VtkOutput, PvdEntryThatCouldNotBeWrittenIsNotKept) {
  TempDir dir;
  const fs::path pvd = dir / "later" / "run.pvd";
  PvdSeries series(pvd);
  EXPECT_THROW(series.add(1.0, "lost.vtp"), std::runtime_error);
  fs::create_directories(dir / "later");
  series.add(2.0, "kept.vtp");
  const auto entries = read_pvd(pvd);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].at("file"), "kept.vtp");
  EXPECT_EQ(std::stod(entries[0].at("timestep")), 2.0);
}

// ---------------------------------------------------------------------------------------
// Checks with external parsers, skipped where they are not installed.

/// The first of the given interpreters for which `python_check` exits 0, or "".
std::string find_python(const std::string& python_check) {
  for (const char* py : {"python3", "/usr/bin/python3"}) {
    const std::string cmd = std::string(py) + " -c '" + python_check + "' >/dev/null 2>&1";
    if (std::system(cmd.c_str()) == 0) return py;
  }
  return "";
}

TEST(VtkOutput, PvdIsWellFormedForPythonsXmlParser) {
  const std::string py = find_python("import xml.dom.minidom");
  if (py.empty()) GTEST_SKIP() << "no python3 with xml.dom.minidom";
  TempDir dir;
  PvdSeries series(dir / "run.pvd");
  series.add(0.0, "a&b.vtp");
  series.add(1.0, "c\"d.vtp", 2);
  const std::string script =
      "import sys, xml.dom.minidom as m\n"
      "d = m.parse(sys.argv[1])\n"
      "s = d.getElementsByTagName('DataSet')\n"
      "ok = [x.getAttribute('file') for x in s] == ['a&b.vtp', 'c\"d.vtp']\n"
      "sys.exit(0 if ok and d.documentElement.tagName == 'VTKFile' else 3)\n";
  std::ofstream(dir / "check.py") << script;
  const std::string cmd = py + " " + (dir / "check.py").string() + " " + (dir / "run.pvd").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0);
}

/// What VTK's vtkXMLPolyDataReader makes of a file, dumped by a Python script.
struct VtkDump {
  std::map<std::string, std::size_t> counts;
  std::vector<int> cell_types;
  std::vector<std::vector<Vector3d>> cell_points;
  std::map<std::string, std::pair<int, std::vector<double>>> arrays;
};

const char* kVtkDumpScript = R"(import sys
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
errors = []
r = vtkXMLPolyDataReader()
r.AddObserver(vtkCommand.ErrorEvent, lambda o, e: errors.append(e))
r.AddObserver(vtkCommand.WarningEvent, lambda o, e: errors.append(e))
r.SetFileName(sys.argv[1])
r.Update()
if errors or r.GetErrorCode() != 0:
    sys.exit(2)
d = r.GetOutput()
w = open(sys.argv[2], "w")
w.write("points %d\nverts %d\nlines %d\npolys %d\n" % (d.GetNumberOfPoints(),
        d.GetNumberOfVerts(), d.GetNumberOfLines(), d.GetNumberOfPolys()))
for c in range(d.GetNumberOfCells()):
    cell = d.GetCell(c)
    ids = cell.GetPointIds()
    xs = [x for k in range(ids.GetNumberOfIds()) for x in d.GetPoint(ids.GetId(k))]
    w.write("cell\t%d\t%s\n" % (cell.GetCellType(), " ".join(repr(x) for x in xs)))
cd = d.GetCellData()
for i in range(cd.GetNumberOfArrays()):
    a = cd.GetArray(i)
    n = a.GetNumberOfComponents()
    vs = [a.GetComponent(t, k) for t in range(a.GetNumberOfTuples()) for k in range(n)]
    w.write("array\t%s\t%d\t%s\n" % (a.GetName(), n, " ".join(repr(v) for v in vs)))
)";

VtkDump vtk_dump(const std::string& py, const fs::path& vtp, const fs::path& dir) {
  std::ofstream(dir / "dump.py") << kVtkDumpScript;
  const fs::path out = dir / (vtp.stem().string() + ".txt");
  const std::string cmd =
      py + " " + (dir / "dump.py").string() + " " + vtp.string() + " " + out.string();
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("VTK could not read " + vtp.string());
  VtkDump dump;
  std::istringstream in(read_bytes(out));
  std::string line;
  auto numbers = [](const std::string& s) {
    std::vector<double> v;
    std::istringstream ns(s);
    std::string word;
    while (ns >> word) v.push_back(std::stod(word));
    return v;
  };
  while (std::getline(in, line)) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
      const auto tab = line.find('\t', start);
      parts.push_back(line.substr(start, tab - start));
      if (tab == std::string::npos) break;
      start = tab + 1;
    }
    if (parts[0] == "cell") {
      dump.cell_types.push_back(std::stoi(parts.at(1)));
      const auto xs = numbers(parts.at(2));
      std::vector<Vector3d> pts;
      for (std::size_t k = 0; k + 2 < xs.size(); k += 3)
        pts.emplace_back(xs[k], xs[k + 1], xs[k + 2]);
      dump.cell_points.push_back(pts);
    } else if (parts[0] == "array") {
      dump.arrays[parts.at(1)] = {std::stoi(parts.at(2)), numbers(parts.at(3))};
    } else {
      std::istringstream ls(line);
      std::string key;
      std::size_t n = 0;
      ls >> key >> n;
      dump.counts[key] = n;
    }
  }
  return dump;
}

TEST(VtkOutput, VtksOwnReaderSeesTheSameBodiesAndLinks) {
  const std::string py = find_python("from vtkmodules.vtkIOXML import vtkXMLPolyDataReader");
  if (py.empty()) GTEST_SKIP() << "no python3 with VTK (Debian: python3-vtk9)";
  TempDir dir;

  const BodyFrame bodies = sample_bodies();
  write_vtp(dir / "bodies.vtp", bodies);
  const VtkDump b = vtk_dump(py, dir / "bodies.vtp", dir.path());
  EXPECT_EQ(b.counts.at("points"), 12u);
  EXPECT_EQ(b.counts.at("polys"), 10u);
  EXPECT_EQ(b.counts.at("verts") + b.counts.at("lines"), 0u);
  ASSERT_EQ(b.cell_points.size(), 10u);
  std::size_t c = 0;
  for (std::size_t body = 0; body < bodies.meshes.size(); ++body) {
    const auto& mesh = bodies.meshes[body];
    for (const auto& face : mesh.faces) {
      ASSERT_EQ(b.cell_points[c].size(), face.size()) << "cell " << c;
      for (std::size_t k = 0; k < face.size(); ++k) {
        EXPECT_EQ(b.cell_points[c][k], mesh.vertices[face[k]]) << "cell " << c;
      }
      EXPECT_EQ(b.arrays.at("mass").second.at(c), bodies.body_fields.scalars.at("mass")[body]);
      EXPECT_TRUE(
          same(b.arrays.at("strain").second.at(c), bodies.body_fields.scalars.at("strain")[body]));
      EXPECT_EQ(b.arrays.at(kOddName).second.at(c), bodies.body_fields.scalars.at(kOddName)[body]);
      EXPECT_EQ(b.arrays.at("grain").second.at(c), bodies.body_fields.ids.at("grain")[body]);
      EXPECT_EQ(b.arrays.at("body_index").second.at(c), static_cast<double>(body));
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(b.arrays.at("velocity").second.at(3 * c + k),
                  bodies.body_fields.vectors.at("velocity")[body][k]);
      }
      ++c;
    }
  }
  EXPECT_EQ(b.arrays.at("velocity").first, 3);

  // VTK numbers cells Verts first, then Lines: whatever order it chose, each cell's field
  // values must be those of the link whose end points the cell has.
  const LinkFrame links = sample_links();
  write_vtp(dir / "links.vtp", links);
  const VtkDump l = vtk_dump(py, dir / "links.vtp", dir.path());
  EXPECT_EQ(l.counts.at("verts"), 2u);
  EXPECT_EQ(l.counts.at("lines"), 3u);
  ASSERT_EQ(l.cell_points.size(), 5u);
  std::set<std::size_t> seen;
  for (std::size_t k = 0; k < 5; ++k) {
    const auto& pts = l.cell_points[k];
    std::size_t link = 5;
    for (std::size_t i = 0; i < 5; ++i) {
      const bool vert = links.a[i] == links.b[i];
      if (vert && pts.size() == 1 && pts[0] == links.a[i]) link = i;
      if (!vert && pts.size() == 2 && pts[0] == links.a[i] && pts[1] == links.b[i]) link = i;
    }
    ASSERT_LT(link, 5u) << "cell " << k << " matches no link";
    seen.insert(link);
    EXPECT_EQ(l.cell_types[k], pts.size() == 1 ? 1 : 3) << "VTK_VERTEX or VTK_LINE";
    EXPECT_EQ(l.arrays.at("force").second.at(k), links.fields.scalars.at("force")[link]);
    EXPECT_EQ(l.arrays.at("contact_id").second.at(k), links.fields.ids.at("contact_id")[link]);
    EXPECT_EQ(l.arrays.at("link_index").second.at(k), static_cast<double>(link));
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(l.arrays.at("normal").second.at(3 * k + j),
                links.fields.vectors.at("normal")[link][j]);
    }
  }
  EXPECT_EQ(seen.size(), 5u);

  write_vtp(dir / "empty.vtp", BodyFrame{});
  EXPECT_EQ(vtk_dump(py, dir / "empty.vtp", dir.path()).counts.at("points"), 0u);
}

}  // namespace

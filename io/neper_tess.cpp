#include "io/neper_tess.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "geometry/laguerre.hpp"
#include "geometry/voronoi.hpp"

namespace cleave::io {

TessellationFileError::TessellationFileError(std::string file, int line, const std::string& message)
    : std::runtime_error(file + ":" + std::to_string(line) + ": " + message),
      file_(std::move(file)),
      line_(line) {}

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string read_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw TessellationFileError(file.string(), 0, "cannot open the file");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Token {
  std::string text;
  int line = 0;
};

/// Whitespace-separated tokens with their line numbers.
class Tokens {
 public:
  Tokens(const std::string& text, std::string name) : name_(std::move(name)) {
    int line = 1;
    std::string cur;
    int cur_line = 1;
    for (char c : text) {
      if (std::isspace(static_cast<unsigned char>(c))) {
        if (!cur.empty()) tokens_.push_back({cur, cur_line});
        cur.clear();
        if (c == '\n') ++line;
        continue;
      }
      if (cur.empty()) cur_line = line;
      cur += c;
    }
    if (!cur.empty()) tokens_.push_back({cur, cur_line});
    last_line_ = line;
  }

  [[noreturn]] void fail(int line, const std::string& message) const {
    throw TessellationFileError(name_, line, message);
  }
  [[noreturn]] void fail_here(const std::string& message) const { fail(line(), message); }
  [[nodiscard]] bool done() const { return pos_ >= tokens_.size(); }
  [[nodiscard]] int line() const { return done() ? last_line_ : tokens_[pos_].line; }
  [[nodiscard]] const std::string& peek() const {
    static const std::string end;
    return done() ? end : tokens_[pos_].text;
  }
  const Token& next(const std::string& what) {
    if (done()) fail(last_line_, "the file ends where " + what + " should be");
    return tokens_[pos_++];
  }
  void expect(const std::string& word) {
    const Token& t = next("'" + word + "'");
    if (t.text != word) fail(t.line, "expected '" + word + "', found '" + t.text + "'");
  }
  double number(const std::string& what) {
    const Token& t = next(what);
    try {
      std::size_t used = 0;
      const double v = std::stod(t.text, &used);
      if (used == t.text.size() && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    fail(t.line, what + ": expected a number, found '" + t.text + "'");
  }
  long integer(const std::string& what, long low = std::numeric_limits<long>::min()) {
    const Token& t = next(what);
    try {
      std::size_t used = 0;
      const long v = std::stol(t.text, &used);
      if (used == t.text.size()) {
        if (v < low)
          fail(t.line, what + ": must be >= " + std::to_string(low) + ", found " + t.text);
        return v;
      }
    } catch (const TessellationFileError&) {
      throw;
    } catch (const std::exception&) {
    }
    fail(t.line, what + ": expected an integer, found '" + t.text + "'");
  }
  /// Skips tokens up to the next one starting with `prefix`.
  void skip_to(const std::string& prefix) {
    while (!done() && tokens_[pos_].text.rfind(prefix, 0) != 0) ++pos_;
  }
  [[nodiscard]] const std::string& name() const { return name_; }

 private:
  std::string name_;
  std::vector<Token> tokens_;
  std::size_t pos_ = 0;
  int last_line_ = 1;
};

bool starts(const std::string& s, const char* prefix) {
  return s.rfind(prefix, 0) == 0;
}

struct FileFace {
  std::vector<int> vertices;  ///< 0-based
  int line = 0;
};

struct DomainFace {
  std::vector<double> params;  ///< d a b c
  int line = 0;
};

/// An exact convex domain from planes a x + b y + c z = d (orientation taken from an interior
/// point): a box around the domain's vertices cut by each plane.
geometry::ExactPolyhedron domain_from_planes(const std::vector<DomainFace>& faces,
                                             const std::vector<Eigen::Vector3d>& vertices,
                                             Tokens& in) {
  Eigen::AlignedBox3d box;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& v : vertices) {
    box.extend(v);
    centre += v / static_cast<double>(vertices.size());
  }
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(0.1 * box.diagonal().norm() + 1e-300);
  geometry::ExactPolyhedron domain = geometry::exact_box(box.min() - margin, box.max() + margin);
  for (const auto& f : faces) {
    Eigen::Vector3d n(f.params[1], f.params[2], f.params[3]);
    double d = f.params[0];
    if (n.dot(centre) - d < 0.0) {  // keep the side holding the domain's centre
      n = -n;
      d = -d;
    }
    if (n.isZero()) in.fail(f.line, "domain face with a zero normal");
    auto kept = domain.clipped(geometry::ExactPlane::from_normal_offset(n, d));
    if (!kept) in.fail(f.line, "domain face leaves no domain on the side of the domain's vertices");
    domain = std::move(*kept);
  }
  return domain;
}

}  // namespace

int neper_descriptor_size(const std::string& descriptor) {
  const std::string des = descriptor.substr(0, descriptor.find(':'));
  if (des == "rodrigues" || des == "euler-bunge") return 3;
  if (des == "axis-angle" || des == "quaternion") return 4;
  if (des == "rotmat") return 9;
  return 0;
}

Eigen::Quaterniond quaternion_from_bunge_degrees(double phi1, double Phi, double phi2) {
  const double d = kPi / 180.0;
  auto rz = [](double a) {
    Eigen::Matrix3d m;
    m << std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a), 0, 0, 0, 1;
    return m;
  };
  Eigen::Matrix3d rx;
  rx << 1, 0, 0, 0, std::cos(Phi * d), std::sin(Phi * d), 0, -std::sin(Phi * d), std::cos(Phi * d);
  const Eigen::Matrix3d g = rz(phi2 * d) * rx * rz(phi1 * d);  // specimen -> crystal
  return Eigen::Quaterniond(Eigen::Matrix3d(g.transpose())).normalized();
}

Eigen::Quaterniond neper_orientation(const std::string& descriptor, const std::vector<double>& p) {
  const std::size_t colon = descriptor.find(':');
  const std::string des = descriptor.substr(0, colon);
  const std::string convention =
      colon == std::string::npos ? "active" : descriptor.substr(colon + 1);
  if (convention != "active" && convention != "passive") {
    throw std::invalid_argument("orientation convention '" + convention +
                                "': expected 'active' or 'passive'");
  }
  const int size = neper_descriptor_size(des);
  if (size == 0) {
    throw std::invalid_argument("orientation descriptor '" + des +
                                "' is not read (rodrigues, euler-bunge, rotmat, axis-angle and "
                                "quaternion are); write the file with -oridescriptor rodrigues");
  }
  if (static_cast<int>(p.size()) != size) {
    throw std::invalid_argument("orientation descriptor '" + des + "' takes " +
                                std::to_string(size) + " values, found " +
                                std::to_string(p.size()));
  }
  // q: the rotation whose passive matrix is Neper's g(params), i.e. g = R(q)^T.
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  if (des == "euler-bunge") {
    q = quaternion_from_bunge_degrees(p[0], p[1], p[2]);
  } else if (des == "rotmat") {
    Eigen::Matrix3d g;
    g << p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8];
    const double err = (g * g.transpose() - Eigen::Matrix3d::Identity()).norm();
    if (err > 1e-6 || g.determinant() < 0.0)
      throw std::invalid_argument("rotmat is not a rotation matrix");
    q = Eigen::Quaterniond(Eigen::Matrix3d(g.transpose()));
  } else if (des == "axis-angle") {
    const Eigen::Vector3d axis(p[0], p[1], p[2]);
    if (axis.norm() == 0.0) throw std::invalid_argument("axis-angle with a zero axis");
    q = Eigen::Quaterniond(Eigen::AngleAxisd(p[3] * kPi / 180.0, axis.normalized()));
  } else if (des == "rodrigues") {
    const Eigen::Vector3d r(p[0], p[1], p[2]);
    q = Eigen::Quaterniond(1.0, r.x(), r.y(), r.z());  // (cos, n sin) / cos of theta/2
  } else if (des == "quaternion") {
    q = Eigen::Quaterniond(p[0], p[1], p[2], p[3]);
    if (q.norm() == 0.0) throw std::invalid_argument("a zero quaternion");
  }
  q.normalize();
  // passive: g maps specimen -> crystal, so crystal -> specimen is g^T = R(q); active: g itself.
  return convention == "passive" ? q : q.conjugate();
}

ImportedTessellation parse_neper_tess(const std::string& text, const std::string& name,
                                      double scale) {
  Tokens in(text, name);
  if (!(scale > 0.0) || !std::isfinite(scale)) in.fail(0, "the scale must be positive");
  in.expect("***tess");
  in.expect("**format");
  {
    const Token& v = in.next("the format version");
    if (!starts(v.text, "3."))
      in.fail(v.line, "format version " + v.text + " is not read (3.x is)");
  }
  in.expect("**general");
  {
    const int line = in.line();
    const long dim = in.integer("the dimension");
    if (dim != 3)
      in.fail(line, "dimension " + std::to_string(dim) + ": cleave reads 3D tessellations only");
    in.next("the tessellation type");
  }
  ImportedTessellation out;
  long cells = -1;
  int cell_line = 0;
  std::vector<Eigen::Vector3d> seeds;
  std::vector<double> radii;
  std::vector<Eigen::Vector3d> vertices;
  std::vector<FileFace> faces;
  std::vector<std::vector<int>> polyhedra;  // signed 1-based faces
  std::vector<int> poly_lines;
  std::vector<Eigen::Vector3d> domain_vertices;
  std::vector<DomainFace> domain_faces;
  std::string domain_type;
  bool ended = false;
  while (!in.done()) {
    const Token section = in.next("a section");
    if (section.text == "***end") {
      ended = true;
      break;
    }
    if (section.text == "**cell") {
      cell_line = section.line;
      cells = in.integer("the number of cells", 1);
      while (starts(in.peek(), "*") && !starts(in.peek(), "**")) {
        const Token sub = in.next("a cell field");
        if (sub.text == "*id") {
          for (long i = 0; i < cells; ++i)
            out.ids.push_back(static_cast<int>(in.integer("a cell id")));
        } else if (sub.text == "*seed") {
          for (long i = 0; i < cells; ++i) {
            const int line = in.line();
            const long id = in.integer("a seed id");
            if (id != i + 1)
              in.fail(line, "seed " + std::to_string(id) + " where seed " + std::to_string(i + 1) +
                                " should be");
            Eigen::Vector3d s;
            for (int d = 0; d < 3; ++d) s[d] = in.number("a seed coordinate");
            seeds.push_back(s * scale);
            radii.push_back(in.number("a seed weight") * scale);
          }
        } else if (sub.text == "*ori") {
          const Token des = in.next("the orientation descriptor");
          const int size = neper_descriptor_size(des.text);
          if (size == 0) {
            in.fail(
                des.line,
                "orientation descriptor '" + des.text +
                    "' is not read (rodrigues, euler-bunge, rotmat, axis-angle, quaternion are)");
          }
          for (long i = 0; i < cells; ++i) {
            const int line = in.line();
            std::vector<double> params;
            for (int k = 0; k < size; ++k)
              params.push_back(in.number("an orientation value of cell " + std::to_string(i + 1)));
            try {
              out.orientations.push_back(neper_orientation(des.text, params));
            } catch (const std::invalid_argument& e) {
              in.fail(line, "cell " + std::to_string(i + 1) + ": " + e.what());
            }
          }
        } else if (sub.text == "*crysym") {
          out.crystal_symmetry = in.next("the crystal symmetry").text;
        } else {
          in.skip_to("*");  // *lam, *mode, *group, *weight, *orispread, ...: not used
        }
      }
    } else if (section.text == "**vertex") {
      const long n = in.integer("the number of vertices", 0);
      for (long i = 0; i < n; ++i) {
        const int line = in.line();
        if (in.integer("a vertex id") != i + 1)
          in.fail(line, "vertex " + std::to_string(i + 1) + " expected here");
        Eigen::Vector3d v;
        for (int d = 0; d < 3; ++d) v[d] = in.number("a vertex coordinate");
        vertices.push_back(v * scale);
        in.integer("a vertex state");
      }
    } else if (section.text == "**edge") {
      const long n = in.integer("the number of edges", 0);
      for (long i = 0; i < n; ++i) {
        for (int k = 0; k < 4; ++k) in.integer("an edge field");
      }
    } else if (section.text == "**face") {
      const long n = in.integer("the number of faces", 0);
      for (long i = 0; i < n; ++i) {
        FileFace f;
        f.line = in.line();
        if (in.integer("a face id") != i + 1)
          in.fail(f.line, "face " + std::to_string(i + 1) + " expected here");
        const long nv = in.integer("the number of vertices of a face", 3);
        for (long k = 0; k < nv; ++k) {
          const int line = in.line();
          const long v = in.integer("a face vertex", 1);
          if (v > static_cast<long>(vertices.size()))
            in.fail(line, "face " + std::to_string(i + 1) + " names vertex " + std::to_string(v) +
                              ", which does not exist");
          f.vertices.push_back(static_cast<int>(v - 1));
        }
        const long ne = in.integer("the number of edges of a face", 0);
        for (long k = 0; k < ne; ++k) in.integer("a face edge");
        for (int k = 0; k < 4; ++k) in.number("a face equation coefficient");
        const int state_line = in.line();
        const long state = in.integer("a face state");
        if (state != 0) {
          in.fail(state_line,
                  "face " + std::to_string(i + 1) + " has state " + std::to_string(state) +
                      ": a regularised tessellation's faces are not planar; give cleave a "
                      "tessellation made without -regularization");
        }
        in.integer("a face point");
        for (int k = 0; k < 3; ++k) in.number("a face point coordinate");
        faces.push_back(std::move(f));
      }
    } else if (section.text == "**polyhedron") {
      const long n = in.integer("the number of polyhedra", 0);
      for (long i = 0; i < n; ++i) {
        poly_lines.push_back(in.line());
        if (in.integer("a polyhedron id") != i + 1)
          in.fail(poly_lines.back(), "polyhedron " + std::to_string(i + 1) + " expected here");
        const long nf = in.integer("the number of faces of a polyhedron", 4);
        std::vector<int> fs;
        for (long k = 0; k < nf; ++k) {
          const int line = in.line();
          const long f = in.integer("a polyhedron face");
          if (f == 0 || std::abs(f) > static_cast<long>(faces.size()))
            in.fail(line, "polyhedron " + std::to_string(i + 1) + " names face " +
                              std::to_string(f) + ", which does not exist");
          fs.push_back(static_cast<int>(f));
        }
        polyhedra.push_back(std::move(fs));
      }
    } else if (section.text == "**domain") {
      while (starts(in.peek(), "*") && !starts(in.peek(), "**")) {
        const Token sub = in.next("a domain field");
        if (sub.text == "*general") {
          domain_type = in.next("the domain type").text;
        } else if (sub.text == "*vertex") {
          const long n = in.integer("the number of domain vertices", 1);
          for (long i = 0; i < n; ++i) {
            in.integer("a domain vertex id");
            Eigen::Vector3d v;
            for (int d = 0; d < 3; ++d) v[d] = in.number("a domain vertex coordinate");
            domain_vertices.push_back(v * scale);
            in.next("a domain vertex label");
            const long k = in.integer("the number of tessellation vertices of a domain vertex", 0);
            for (long j = 0; j < k; ++j) in.integer("a tessellation vertex");
          }
        } else if (sub.text == "*face") {
          const long n = in.integer("the number of domain faces", 1);
          for (long i = 0; i < n; ++i) {
            DomainFace f;
            f.line = in.line();
            in.integer("a domain face id");
            const long nv = in.integer("the number of vertices of a domain face", 0);
            for (long k = 0; k < nv; ++k) in.integer("a domain face vertex");
            const long ne = in.integer("the number of edges of a domain face", 0);
            for (long k = 0; k < ne; ++k) in.integer("a domain face edge");
            const Token type = in.next("the domain face type");
            if (type.text != "plane") {
              in.fail(type.line, "domain face " + std::to_string(i + 1) + " is a " + type.text +
                                     ": cleave reads domains bounded by planes only");
            }
            const int params_line = in.line();
            const long np = in.integer("the number of domain face parameters", 0);
            if (np != 4)
              in.fail(params_line, "a plane domain face takes 4 parameters (d a b c), found " +
                                       std::to_string(np));
            for (int k = 0; k < 4; ++k) f.params.push_back(in.number("a domain face parameter"));
            f.params[0] *= scale;
            in.next("a domain face label");
            const long nt = in.integer("the number of tessellation faces of a domain face", 0);
            for (long k = 0; k < nt; ++k) in.integer("a tessellation face");
            domain_faces.push_back(std::move(f));
          }
        } else {
          in.skip_to("*");
        }
      }
    } else if (section.text == "**periodicity" || section.text == "**periodic") {
      in.fail(section.line, "a periodic tessellation is not read; give cleave a non-periodic one");
    } else if (starts(section.text, "**")) {
      in.skip_to("**");  // **scale and others: not used
    } else {
      in.fail(section.line,
              "expected a section (**cell, **vertex, ...), found '" + section.text + "'");
    }
  }
  if (!ended) in.fail(in.line(), "the file ends without ***end");
  if (cells < 0) in.fail(0, "no **cell section");
  if (seeds.empty()) {
    in.fail(cell_line,
            "**cell has no *seed: cleave rebuilds the cells exactly from their seeds and weights");
  }
  if (!out.ids.empty() && static_cast<long>(out.ids.size()) != cells)
    in.fail(cell_line, "*id count differs from the number of cells");
  if (out.ids.empty()) {
    for (long i = 0; i < cells; ++i) out.ids.push_back(static_cast<int>(i + 1));
  }
  if (static_cast<long>(polyhedra.size()) != cells) {
    in.fail(cell_line, std::to_string(cells) + " cells but " + std::to_string(polyhedra.size()) +
                           " polyhedra");
  }
  if (domain_faces.size() < 4 || domain_vertices.size() < 4)
    in.fail(0, "no **domain with its *vertex and *face fields");

  const geometry::ExactPolyhedron domain = domain_from_planes(domain_faces, domain_vertices, in);
  out.domain_volume = domain.volume();
  out.seeds = seeds;
  for (double r : radii) out.weights.push_back(r * r);  // Neper's power: |x - s|^2 - w^2
  try {
    out.cells = geometry::laguerre_cells(domain, out.seeds, out.weights);
  } catch (const std::invalid_argument& e) {
    in.fail(cell_line, std::string("the cells cannot be rebuilt from their seeds: ") + e.what() +
                           " (0-based)");
  }
  if (geometry::total_volume(out.cells) != out.domain_volume) {
    in.fail(cell_line,
            "internal error: the rebuilt cells' exact volumes do not sum to the domain's");
  }
  // Cross-check each rebuilt cell against the file's vertices, both ways.
  Eigen::AlignedBox3d box;
  for (const auto& v : domain_vertices) box.extend(v);
  const double tolerance = kTessVertexTolerance * box.diagonal().norm();
  for (std::size_t i = 0; i < polyhedra.size(); ++i) {
    std::vector<Eigen::Vector3d> file_vertices;
    for (int f : polyhedra[i]) {
      for (int v : faces[static_cast<std::size_t>(std::abs(f) - 1)].vertices)
        file_vertices.push_back(vertices[static_cast<std::size_t>(v)]);
    }
    const auto rebuilt = out.cells[i].vertices_approx();
    auto farthest = [](const std::vector<Eigen::Vector3d>& from,
                       const std::vector<Eigen::Vector3d>& to, Eigen::Vector3d* where) {
      double worst = 0.0;
      for (const auto& a : from) {
        double best = std::numeric_limits<double>::infinity();
        for (const auto& b : to) best = std::min(best, (a - b).norm());
        if (best > worst) {
          worst = best;
          *where = a;
        }
      }
      return worst;
    };
    Eigen::Vector3d at = Eigen::Vector3d::Zero();
    const double off_file = farthest(file_vertices, rebuilt, &at);
    const double off_rebuilt =
        off_file > tolerance ? off_file : farthest(rebuilt, file_vertices, &at);
    if (std::max(off_file, off_rebuilt) > tolerance) {
      std::ostringstream msg;
      msg << "cell " << out.ids[i] << " (polyhedron " << i + 1
          << ") rebuilt from its seed and weight "
          << "differs from the file's vertices: a vertex at (" << at.x() / scale << ", "
          << at.y() / scale << ", " << at.z() / scale << ") is "
          << std::max(off_file, off_rebuilt) / scale
          << " from the other's, more than the tolerance " << tolerance / scale
          << " (file lengths); the seeds, weights or vertices do not belong together";
      in.fail(poly_lines[i], msg.str());
    }
  }
  return out;
}

ImportedTessellation read_neper_tess(const std::filesystem::path& file, double scale) {
  return parse_neper_tess(read_text(file), file.string(), scale);
}

ImportedTessellation parse_grain_file(const std::string& text, const std::string& name,
                                      double scale, const Eigen::Vector3d& size) {
  std::istringstream lines(text);
  std::string raw;
  int line = 0;
  std::vector<Eigen::Vector3d> centres;
  std::vector<double> volumes;
  std::vector<int> line_of;
  ImportedTessellation out;
  while (std::getline(lines, raw)) {
    ++line;
    const std::string content = raw.substr(0, raw.find('#'));
    std::istringstream fields(content);
    std::vector<std::string> words;
    for (std::string w; fields >> w;) words.push_back(w);
    if (words.empty()) continue;
    if (words.size() != 7) {
      throw TessellationFileError(
          name, line,
          "expected 7 values (x y z volume phi1 Phi phi2), found " + std::to_string(words.size()));
    }
    static const char* const kNames[] = {"x", "y", "z", "volume", "phi1", "Phi", "phi2"};
    double v[7];
    for (int k = 0; k < 7; ++k) {
      try {
        std::size_t used = 0;
        v[k] = std::stod(words[static_cast<std::size_t>(k)], &used);
        if (used != words[static_cast<std::size_t>(k)].size() || !std::isfinite(v[k]))
          throw std::invalid_argument("");
      } catch (const std::exception&) {
        throw TessellationFileError(name, line,
                                    std::string(kNames[k]) + ": expected a number, found '" +
                                        words[static_cast<std::size_t>(k)] + "'");
      }
    }
    const Eigen::Vector3d c = Eigen::Vector3d(v[0], v[1], v[2]) * scale;
    for (int d = 0; d < 3; ++d) {
      if (!(c[d] > 0.0 && c[d] < size[d])) {
        throw TessellationFileError(name, line,
                                    std::string("centroid ") + kNames[d] + " = " +
                                        words[static_cast<std::size_t>(d)] +
                                        " lies outside the box");
      }
    }
    if (!(v[3] > 0.0))
      throw TessellationFileError(name, line, "volume must be positive, found " + words[3]);
    for (std::size_t k = 0; k < centres.size(); ++k) {
      if (centres[k] == c)
        throw TessellationFileError(name, line,
                                    "the same centroid as line " + std::to_string(line_of[k]));
    }
    centres.push_back(c);
    volumes.push_back(v[3] * scale * scale * scale);
    line_of.push_back(line);
    out.orientations.push_back(quaternion_from_bunge_degrees(v[4], v[5], v[6]));
  }
  if (centres.empty())
    throw TessellationFileError(name, 0, "no grains (one a line: x y z volume phi1 Phi phi2)");
  double sum = 0.0;
  for (double v : volumes) sum += v;
  const double box = size.x() * size.y() * size.z();
  if (std::abs(sum / box - 1.0) > 0.01) {
    std::ostringstream msg;
    msg << "the grains' volumes sum to " << sum << " m^3, " << 100.0 * (sum / box - 1.0)
        << "% off the box's " << box << " m^3 (1% allowed)";
    throw TessellationFileError(name, 0, msg.str());
  }
  geometry::LaguerreTessellation t = geometry::fitted_laguerre(size, centres, volumes);
  if (t.fit.max_relative_error > 0.01) {
    throw TessellationFileError(
        name, 0,
        "no Laguerre weights give these centroids their volumes (a cell is " +
            std::to_string(100.0 * t.fit.max_relative_error) +
            "% off its volume): check the centroids and volumes");
  }
  out.cells = std::move(t.cells);
  out.seeds = std::move(t.points);
  out.weights = std::move(t.fit.weights);
  for (std::size_t i = 0; i < centres.size(); ++i) out.ids.push_back(static_cast<int>(i + 1));
  out.domain_volume = geometry::exact_box(Eigen::Vector3d::Zero(), size).volume();
  if (geometry::total_volume(out.cells) != out.domain_volume) {
    throw TessellationFileError(name, 0,
                                "internal error: the cells' exact volumes do not sum to the box's");
  }
  return out;
}

ImportedTessellation read_grain_file(const std::filesystem::path& file, double scale,
                                     const Eigen::Vector3d& size) {
  return parse_grain_file(read_text(file), file.string(), scale, size);
}

}  // namespace cleave::io

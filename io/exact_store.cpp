#include "io/exact_store.hpp"

#include <fmt/format.h>

#include <map>
#include <sstream>
#include <stdexcept>

#include "io/result_dir.hpp"

namespace cleave::io {

ExactStore make_exact_store(const geometry::Specimen& specimen,
                            const std::vector<geometry::Piece>& pieces) {
  ExactStore store;
  std::map<const geometry::ExactPolyhedron*, int> index;
  auto shape_id = [&](const geometry::ExactPolyhedron* shape) {
    auto [it, fresh] = index.try_emplace(shape, static_cast<int>(store.shapes.size()));
    if (fresh) store.shapes.push_back(*shape);
    return it->second;
  };
  for (const auto& g : specimen.grains) {
    store.grains.push_back({geometry::Lineage{g.id, {}}, shape_id(&specimen.shape_of(g)), g.site.centre});
  }
  for (const auto& p : pieces) {
    store.fragments.push_back({p.lineage, shape_id(p.shape.get()), p.position});
  }
  return store;
}

std::string to_text(const ExactStore& store) {
  std::string out = "cleave-exact 1\n";
  for (std::size_t s = 0; s < store.shapes.size(); ++s) {
    out += fmt::format("shape {}\n{}end\n", s, store.shapes[s].to_exact_text());
  }
  auto placement = [&](const char* kind, const ExactStore::Placement& p) {
    out += fmt::format("{} {} shape {} position {:.17g} {:.17g} {:.17g}\n", kind,
                       p.lineage.path_string(), p.shape, p.position.x(), p.position.y(),
                       p.position.z());
  };
  for (const auto& g : store.grains) placement("grain", g);
  for (const auto& f : store.fragments) placement("fragment", f);
  return out;
}

namespace {

geometry::Lineage parse_lineage(const std::string& text) {
  geometry::Lineage l;
  std::istringstream in(text);
  std::string part;
  bool first = true;
  while (std::getline(in, part, '.')) {
    std::size_t used = 0;
    const int v = std::stoi(part, &used);
    if (used != part.size() || v < 0) throw std::invalid_argument(text);
    if (first) {
      l.grain_id = v;
      first = false;
    } else {
      l.path.push_back(v);
    }
  }
  if (first) throw std::invalid_argument(text);
  return l;
}

}  // namespace

ExactStore parse_exact_store(const std::string& text, const std::string& source) {
  ExactStore store;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& message) {
    return std::runtime_error(fmt::format("{}:{}: {}", source, line_no, message));
  };
  if (!std::getline(in, line) || line != "cleave-exact 1") {
    line_no = 1;
    throw fail("not a cleave exact geometry file (expected 'cleave-exact 1')");
  }
  line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "shape") {
      std::size_t id = 0;
      if (!(words >> id) || id != store.shapes.size()) throw fail("shapes must be numbered 0, 1, ...");
      const int start = line_no;
      std::string body, l;
      bool closed = false;
      while (std::getline(in, l)) {
        ++line_no;
        if (l == "end") {
          closed = true;
          break;
        }
        body += l + '\n';
      }
      if (!closed) throw fail(fmt::format("shape {} (line {}) has no 'end'", id, start));
      try {
        store.shapes.push_back(geometry::ExactPolyhedron::from_exact_text(body));
      } catch (const geometry::GeometryError& e) {
        line_no = start;
        throw fail(fmt::format("shape {}: {}", id, e.what()));
      }
    } else if (kind == "grain" || kind == "fragment") {
      std::string path, shape_word, position_word;
      ExactStore::Placement p;
      if (!(words >> path >> shape_word >> p.shape >> position_word >> p.position.x() >>
            p.position.y() >> p.position.z()) ||
          shape_word != "shape" || position_word != "position") {
        throw fail("expected '" + kind + " PATH shape S position X Y Z'");
      }
      try {
        p.lineage = parse_lineage(path);
      } catch (const std::exception&) {
        throw fail("bad lineage path '" + path + "'");
      }
      if (p.shape < 0 || p.shape >= static_cast<int>(store.shapes.size())) {
        throw fail(fmt::format("shape {} is not defined above", p.shape));
      }
      // A fragment with a plain id is a grain that stayed whole (a run's final pieces).
      if (kind == "grain" && !p.lineage.path.empty()) {
        throw fail("a grain has a plain id; a path like 17.0 names a fragment");
      }
      (kind == "grain" ? store.grains : store.fragments).push_back(std::move(p));
    } else {
      throw fail("unknown record '" + kind + "'");
    }
  }
  return store;
}

void write_exact_store(const std::filesystem::path& file, const ExactStore& store) {
  write_file_atomically(file, to_text(store));
}

ExactStore read_exact_store(const std::filesystem::path& file) {
  return parse_exact_store(read_file(file), file.string());
}

}  // namespace cleave::io

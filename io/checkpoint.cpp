#include "io/checkpoint.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "io/budget.hpp"
#include "io/exact_store.hpp"
#include "io/result_dir.hpp"
#include "physics/dem/state_codec.hpp"

namespace cleave::io {

namespace {

namespace fs = std::filesystem;
using physics::StateReader;
using physics::StateWriter;

constexpr std::size_t kHeaderBytes = 24;
constexpr std::size_t kChecksumBytes = 64;

void put_book(StateWriter& w, const physics::FractureBook& book) {
  const physics::FractureBook::Saved s = book.save();
  w.put(s.dilation_radius);
  w.put(s.min_fragment_fraction);
  // The exact shapes, exactly, in the text of geometry.exact (io/exact_store.hpp).
  ExactStore store;
  std::map<const geometry::ExactPolyhedron*, int> index;
  w.count(s.shapes.size());
  for (const auto& [world_index, exact] : s.shapes) {
    auto [it, fresh] = index.try_emplace(exact.get(), static_cast<int>(store.shapes.size()));
    if (fresh) store.shapes.push_back(*exact);
    w.put(world_index);
    w.put<std::int32_t>(it->second);
  }
  w.put(to_text(store));
  w.count(s.cuts.size());
  for (const auto& c : s.cuts) {
    w.put(c.shape);
    w.put(c.plane);
    w.put(c.pieces);
  }
  w.count(s.plane_sets.size());
  for (const auto& set : s.plane_sets) {
    w.count(set->size());
    for (const auto& p : *set) w.put(p.to_string());
  }
  w.count(s.bodies.size());
  for (const auto& b : s.bodies) {
    w.put(b.generation);
    w.put(b.used);
    w.put<std::int32_t>(b.lineage.grain_id);
    w.count(b.lineage.path.size());
    for (int p : b.lineage.path) w.put<std::int32_t>(p);
    w.put(b.shape);
    w.put<std::int32_t>(b.plane_set);
    w.count(b.candidates.size());
    for (int c : b.candidates) w.put<std::int32_t>(c);
    w.count(b.opened.size());
    for (const auto& [plane, time] : b.opened) {
      w.put<std::int32_t>(plane);
      w.put(time);
    }
  }
}

physics::FractureBook get_book(StateReader& r, const physics::World& world, const std::string& source) {
  physics::FractureBook::Saved s;
  s.dilation_radius = r.get<double>();
  s.min_fragment_fraction = r.get<double>();
  std::vector<std::pair<std::uint32_t, std::int32_t>> shape_refs(r.count(8));
  for (auto& [world_index, store_index] : shape_refs) {
    world_index = r.get<std::uint32_t>();
    store_index = r.get<std::int32_t>();
  }
  const std::size_t text_at = r.position();
  const std::string text = r.string();
  ExactStore store;
  try {
    store = parse_exact_store(text, fmt::format("{} (exact shapes at byte {})", source, text_at));
  } catch (const std::runtime_error& e) {
    r.fail(e.what());
  }
  std::vector<std::shared_ptr<const geometry::ExactPolyhedron>> shared;
  for (const auto& shape : store.shapes) shared.push_back(std::make_shared<const geometry::ExactPolyhedron>(shape));
  for (const auto& [world_index, store_index] : shape_refs) {
    if (store_index < 0 || static_cast<std::size_t>(store_index) >= shared.size()) {
      r.fail("an exact shape index is out of range");
    }
    s.shapes.emplace_back(world_index, shared[static_cast<std::size_t>(store_index)]);
  }
  s.cuts.resize(r.count(16));
  for (auto& c : s.cuts) {
    c.shape = r.get<std::uint32_t>();
    c.plane = r.string();
    c.pieces = r.numbers<std::uint32_t>();
  }
  s.plane_sets.resize(r.count(8));
  for (auto& set : s.plane_sets) {
    std::vector<geometry::ExactPlane> planes;
    const std::size_t n = r.count(8);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t at = r.position();
      const std::string p = r.string();
      try {
        planes.push_back(geometry::ExactPlane::parse(p));
      } catch (const std::exception& e) {
        throw physics::StateError(at, fmt::format("at byte {}: bad exact plane '{}': {}", at, p, e.what()));
      }
    }
    set = std::make_shared<const std::vector<geometry::ExactPlane>>(std::move(planes));
  }
  s.bodies.resize(r.count(24));
  for (auto& b : s.bodies) {
    b.generation = r.get<std::uint32_t>();
    b.used = r.get_bool();
    b.lineage.grain_id = r.get<std::int32_t>();
    b.lineage.path.resize(r.count(4));
    for (int& p : b.lineage.path) p = r.get<std::int32_t>();
    b.shape = r.get<std::uint32_t>();
    b.plane_set = r.get<std::int32_t>();
    b.candidates.resize(r.count(4));
    for (int& c : b.candidates) c = r.get<std::int32_t>();
    b.opened.resize(r.count(12));
    for (auto& [plane, time] : b.opened) {
      plane = r.get<std::int32_t>();
      time = r.get<double>();
    }
  }
  try {
    return physics::FractureBook::restore(s, world);
  } catch (const std::invalid_argument& e) {
    r.fail(e.what());
  }
}

}  // namespace

std::string encode_checkpoint(const CheckpointMeta& meta, const physics::World& world,
                              const physics::FractureBook* book, std::string_view run_state) {
  StateWriter w;
  w.reserve(1 << 20);
  w.put(meta.cleave_version);
  w.put(meta.scenario_source);
  w.put(meta.scenario_text);
  w.put(meta.max_steps);
  w.put(meta.started_ticks);
  world.save_state(w);
  w.put(book != nullptr);
  if (book) put_book(w, *book);
  w.put(run_state);
  std::string payload = w.take();

  std::string out;
  out.reserve(kHeaderBytes + payload.size() + kChecksumBytes);
  out.append(kCheckpointMagic);
  StateWriter header;
  header.put(kCheckpointVersion);
  header.put<std::uint32_t>(0);
  header.put<std::uint64_t>(payload.size());
  out += header.bytes();
  out += payload;
  out += sha256_hex(out);
  return out;
}

Checkpoint decode_checkpoint(std::string_view bytes, const std::string& source) {
  auto fail = [&](const std::string& what) { return CheckpointError(fmt::format("{}: {}", source, what)); };
  if (bytes.size() < kHeaderBytes) {
    if (bytes.size() >= kCheckpointMagic.size() && bytes.substr(0, kCheckpointMagic.size()) != kCheckpointMagic) {
      throw fail("not a cleave checkpoint (it does not start with \"CLEAVECK\")");
    }
    throw fail(fmt::format("truncated at byte {} (the header alone is {} bytes)", bytes.size(), kHeaderBytes));
  }
  if (bytes.substr(0, kCheckpointMagic.size()) != kCheckpointMagic) {
    throw fail("not a cleave checkpoint (it does not start with \"CLEAVECK\")");
  }
  StateReader header(bytes.substr(8, 16), 8);
  const auto version = header.get<std::uint32_t>();
  header.get<std::uint32_t>();
  const auto length = header.get<std::uint64_t>();
  if (version != kCheckpointVersion) {
    throw fail(fmt::format("version {} not supported (this cleave reads version {})", version,
                           kCheckpointVersion));
  }
  const std::size_t available = bytes.size() - kHeaderBytes;
  if (available < kChecksumBytes || length > available - kChecksumBytes) {
    throw fail(fmt::format("truncated at byte {} (a complete checkpoint has {} bytes)", bytes.size(),
                           length > bytes.size() ? std::string("more") : std::to_string(kHeaderBytes + length + kChecksumBytes)));
  }
  const std::size_t end = kHeaderBytes + static_cast<std::size_t>(length);
  if (bytes.size() != end + kChecksumBytes) {
    throw fail(fmt::format("{} bytes after the checksum at byte {} (a complete checkpoint has {} bytes)",
                           bytes.size() - end - kChecksumBytes, end + kChecksumBytes, end + kChecksumBytes));
  }
  const std::string_view stored = bytes.substr(end, kChecksumBytes);
  const std::string actual = sha256_hex(bytes.substr(0, end));
  if (stored != actual) {
    throw fail(fmt::format("checksum mismatch: the file is corrupted (SHA-256 of bytes 0..{} is {}, "
                           "the file says {})",
                           end, actual.substr(0, 16) + "...", std::string(stored.substr(0, 16)) + "..."));
  }
  StateReader r(bytes.substr(kHeaderBytes, static_cast<std::size_t>(length)), kHeaderBytes);
  Checkpoint ck;
  try {
    ck.meta.cleave_version = r.string();
    ck.meta.scenario_source = r.string();
    ck.meta.scenario_text = r.string();
    ck.meta.max_steps = r.get<std::uint64_t>();
    ck.meta.started_ticks = r.get<std::int64_t>();
    ck.world.load_state(r);
    if (r.get_bool()) ck.book.emplace(get_book(r, ck.world, source));
    ck.run_state = r.string();
    if (!r.done()) r.fail("unread bytes before the checksum");
  } catch (const physics::StateError& e) {
    throw fail(fmt::format("malformed checkpoint {}", e.what()));
  }
  return ck;
}

void write_checkpoint_file(const fs::path& file, std::string_view bytes) {
  const fs::path tmp = file.string() + ".tmp";
  // errno is taken where the call failed, and the half-written .tmp does not stay behind.
  auto fail = [&](const std::string& what, int err, int fd) {
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    return CheckpointError(fmt::format("{}: {}: {}", file.string(), what, std::strerror(err)));
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw fail("cannot open " + tmp.filename().string() + " for writing", errno, -1);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw fail("cannot write", errno, fd);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) throw fail("cannot write (fsync)", errno, fd);
  if (::close(fd) != 0) throw fail("cannot write (close)", errno, -1);
  if (::rename(tmp.c_str(), file.c_str()) != 0) throw fail("cannot rename into place", errno, -1);
  // The rename itself is durable once the folder is synced.
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

fs::path checkpoint_file(const fs::path& path) {
  std::error_code ec;
  return fs::is_directory(path, ec) ? path / kCheckpointName : path;
}

Checkpoint read_checkpoint(const fs::path& path) {
  const fs::path file = checkpoint_file(path);
  if (const std::string problem = input_file_problem(file);
      !problem.empty() && problem != "does not exist")
    throw CheckpointError(file.string() + ": cannot be read: it " + problem +
                          "; cleave reads only regular files");
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw CheckpointError(file.string() +
                          ": cannot be read (no checkpoint there): " + std::strerror(errno));
  std::ostringstream ss;
  ss << in.rdbuf();
  return decode_checkpoint(ss.str(), file.string());
}

}  // namespace cleave::io

#include "parallel/mpi_domain.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <type_traits>

#include "physics/dem/exchange.hpp"

namespace cleave::parallel {

namespace {

using physics::BodyState;
using physics::BondDynamic;
using physics::Exchange;
using physics::HistoryEntry;
using physics::Role;
using physics::WallForceAt;
using physics::World;

/// Plain bytes in and out of a buffer: states, histories and bonds are plain data (doubles,
/// integers and Eigen's fixed-size arrays of doubles), and every process is this binary on
/// this machine type, so their bytes travel as they are.
struct Packer {
  std::vector<char>& out;
  template <class T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const char*>(&v);
    out.insert(out.end(), p, p + sizeof(T));
  }
};

struct Unpacker {
  const std::vector<char>& in;
  std::size_t at = 0;
  [[nodiscard]] bool more() const { return at < in.size(); }
  template <class T>
  T get() {
    if (at + sizeof(T) > in.size()) throw std::logic_error("MpiDomain: a message ended early");
    T v;
    std::memcpy(static_cast<void*>(&v), in.data() + at, sizeof(T));
    at += sizeof(T);
    return v;
  }
  /// A count, then that many T, each handed to `f`.
  template <class T, class F>
  void each(F&& f) {
    const auto n = get<std::uint64_t>();
    for (std::uint64_t k = 0; k < n; ++k) f(get<T>());
  }
};

/// A body's slot and state, as gathered.
struct OwnedState {
  std::uint32_t slot;
  BodyState state;
};

/// A contact record with its place in the one-process order: pairs by (A, B), then walls.
struct RecordAt {
  std::uint32_t group;  // 0 pairs, 1 walls
  std::uint32_t first, second;
  std::uint64_t order;
  physics::ContactRecord record;
};

class Timer {
 public:
  explicit Timer(double& total) : total_(total), t0_(std::chrono::steady_clock::now()) {}
  ~Timer() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count(); }
  Timer(const Timer&) = delete;
  Timer& operator=(const Timer&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace

// ---------------------------------------------------------------------------------------
MpiSession::MpiSession(int& argc, char**& argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);  // OpenMP threads do not call MPI
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

bool launched_by_mpirun() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"}) {
    if (std::getenv(v) != nullptr) return true;
  }
  return false;
}

// ---------------------------------------------------------------------------------------
Bisection::Bisection(std::vector<Point> points, int parts) {
  if (parts < 1) throw std::invalid_argument("Bisection: at least one part");
  constexpr double inf = std::numeric_limits<double>::infinity();
  lo_.assign(static_cast<std::size_t>(parts), Eigen::Vector3d::Constant(-inf));
  hi_.assign(static_cast<std::size_t>(parts), Eigen::Vector3d::Constant(inf));
  build(points, 0, points.size(), 0, parts, Eigen::Vector3d::Constant(-inf), Eigen::Vector3d::Constant(inf));
}

int Bisection::build(std::vector<Point>& points, std::size_t first, std::size_t last, int first_part,
                     int parts, Eigen::Vector3d lo, Eigen::Vector3d hi) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (parts == 1) {
    nodes_[index].part = first_part;
    lo_[first_part] = lo;
    hi_[first_part] = hi;
    return index;
  }
  // The longest extent of this part's bodies (x when it has none).
  int axis = 0;
  if (last > first) {
    Eigen::Vector3d a = points[first].x, b = a;
    for (std::size_t i = first; i < last; ++i) {
      a = a.cwiseMin(points[i].x);
      b = b.cwiseMax(points[i].x);
    }
    (b - a).maxCoeff(&axis);
  }
  std::sort(points.begin() + static_cast<std::ptrdiff_t>(first), points.begin() + static_cast<std::ptrdiff_t>(last),
            [axis](const Point& p, const Point& q) {
              return p.x[axis] < q.x[axis] || (p.x[axis] == q.x[axis] && p.slot < q.slot);
            });
  const int left_parts = parts / 2;
  const std::size_t n = last - first;
  const std::size_t k = first + (n * static_cast<std::size_t>(left_parts) + static_cast<std::size_t>(parts) / 2) /
                                    static_cast<std::size_t>(parts);
  double at = 0.0;
  if (n == 0) {
    at = std::isfinite(lo[axis]) && std::isfinite(hi[axis]) ? 0.5 * (lo[axis] + hi[axis]) : 0.0;
  } else if (k == first) {
    at = points[first].x[axis];
  } else if (k == last) {
    at = std::nextafter(points[last - 1].x[axis], std::numeric_limits<double>::infinity());
  } else {
    at = 0.5 * (points[k - 1].x[axis] + points[k].x[axis]);
  }
  // Ties at the cut go right (owner() sends x >= at right): split where the points say so.
  std::size_t split = first;
  while (split < last && points[split].x[axis] < at) ++split;
  Eigen::Vector3d left_hi = hi, right_lo = lo;
  left_hi[axis] = at;
  right_lo[axis] = at;
  nodes_[index].axis = axis;
  nodes_[index].at = at;
  const int left = build(points, first, split, first_part, left_parts, lo, left_hi);
  const int right = build(points, split, last, first_part + left_parts, parts - left_parts, right_lo, hi);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

int Bisection::owner(const Eigen::Vector3d& x) const {
  int i = 0;
  while (nodes_[i].axis >= 0) i = x[nodes_[i].axis] < nodes_[i].at ? nodes_[i].left : nodes_[i].right;
  return nodes_[i].part;
}

double Bisection::distance(int p, const Eigen::Vector3d& x) const {
  const Eigen::Vector3d below = (lo_[p] - x).cwiseMax(0.0), above = (x - hi_[p]).cwiseMax(0.0);
  return (below + above).norm();
}

// ---------------------------------------------------------------------------------------
MpiDomain::MpiDomain(double rebalance) : rebalance_(rebalance) {
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  if (!(rebalance > 1.0)) throw std::invalid_argument("MpiDomain: the rebalance threshold must be > 1");
}

void MpiDomain::attach(World& world) {
  // Every process holds the same whole world here. The skin is the search's (World::
  // body_contacts: a fraction of the smallest bounding radius); the halo reaches every body
  // that can touch or be bonded to an owned one until some body has moved half the skin.
  double smallest = std::numeric_limits<double>::infinity(), largest = 0.0;
  for (const physics::BodyId id : world.body_ids()) {
    const double r = world.shape(world.info(id).shape).bounding_radius();
    smallest = std::min(smallest, r);
    largest = std::max(largest, r);
  }
  if (world.body_count() == 0) smallest = largest = 0.0;
  skin_ = world.settings().search_skin * smallest;
  halo_ = 2.2 * largest + 2.0 * skin_;
  attached_ = true;
  repartition(world, true);
}

std::vector<std::vector<char>> MpiDomain::all_to_all(const std::vector<std::vector<char>>& out) {
  Timer timer(stats_.communication_seconds);
  const auto n = static_cast<std::size_t>(size_);
  std::vector<int> send_counts(n), recv_counts(n), send_at(n), recv_at(n);
  std::vector<char> sendbuf;
  for (std::size_t r = 0; r < n; ++r) {
    send_counts[r] = static_cast<int>(out[r].size());
    send_at[r] = static_cast<int>(sendbuf.size());
    sendbuf.insert(sendbuf.end(), out[r].begin(), out[r].end());
    if (static_cast<int>(r) != rank_) stats_.bytes_sent += out[r].size();
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (std::size_t r = 0; r < n; ++r) {
    recv_at[r] = total;
    total += recv_counts[r];
  }
  std::vector<char> recvbuf(static_cast<std::size_t>(total));
  MPI_Alltoallv(sendbuf.data(), send_counts.data(), send_at.data(), MPI_BYTE, recvbuf.data(), recv_counts.data(),
                recv_at.data(), MPI_BYTE, MPI_COMM_WORLD);
  std::vector<std::vector<char>> in(n);
  for (std::size_t r = 0; r < n; ++r)
    in[r].assign(recvbuf.begin() + recv_at[r], recvbuf.begin() + recv_at[r] + recv_counts[r]);
  return in;
}

std::vector<std::vector<char>> MpiDomain::all_gather(const std::vector<char>& mine) {
  Timer timer(stats_.communication_seconds);
  const auto n = static_cast<std::size_t>(size_);
  std::vector<int> counts(n), at(n);
  const int count = static_cast<int>(mine.size());
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (std::size_t r = 0; r < n; ++r) {
    at[r] = total;
    total += counts[r];
  }
  stats_.bytes_sent += mine.size() * (n - 1);
  std::vector<char> all(static_cast<std::size_t>(total));
  MPI_Allgatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), at.data(), MPI_BYTE, MPI_COMM_WORLD);
  std::vector<std::vector<char>> in(n);
  for (std::size_t r = 0; r < n; ++r) in[r].assign(all.begin() + at[r], all.begin() + at[r] + counts[r]);
  return in;
}

void MpiDomain::repartition(World& world, bool first) {
  const auto t0 = std::chrono::steady_clock::now();
  Exchange ex = world.exchange();
  std::vector<Role> roles(ex.slots(), Role::dormant);
  ex.take_bodies_changed();
  bool rebalanced = false;
  if (first) {
    // Every process knows every body: the same cuts everywhere, no messages.
    std::vector<Bisection::Point> points;
    for (const physics::BodyId id : world.body_ids())
      points.push_back({ex.state(id.index).x, id.index});
    cuts_ = Bisection(std::move(points), size_);
    for (const physics::BodyId id : world.body_ids()) {
      if (cuts_.owner(ex.state(id.index).x) == rank_) roles[id.index] = Role::owned;
    }
    rebalanced = true;
  } else {
    rebalanced = recut(ex);
    migrate(ex, roles);
  }
  send_ghosts(ex, roles);
  stats_.owned = static_cast<std::size_t>(std::count(roles.begin(), roles.end(), Role::owned));
  stats_.ghosts = static_cast<std::size_t>(std::count(roles.begin(), roles.end(), Role::ghost));
  if (first) {
    world.set_domain(this, std::move(roles));
  } else {
    world.set_roles(std::move(roles));
  }
  ++stats_.repartitions;
  if (rebalanced) {
    ++stats_.rebalances;
    stats_.rebalance_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
}

bool MpiDomain::recut(const Exchange& ex) {
  // Re-cut when the load has drifted: every process's centroids to every process.
  const std::size_t slots = ex.slots();
  const auto n = static_cast<std::size_t>(size_);
  std::uint64_t mine = 0;
  for (std::uint32_t i = 0; i < slots; ++i) mine += ex.owned(i);
  std::uint64_t most = 0, total = 0;
  {
    Timer timer(stats_.communication_seconds);
    MPI_Allreduce(&mine, &most, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD);
    MPI_Allreduce(&mine, &total, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  }
  if (!(total > 0 && static_cast<double>(most) >
                         rebalance_ * static_cast<double>(total) / static_cast<double>(n)))
    return false;
  std::vector<char> buf;
  Packer pk{buf};
  for (std::uint32_t i = 0; i < slots; ++i) {
    if (ex.owned(i)) pk.put(Bisection::Point{ex.state(i).x, i});
  }
  std::vector<Bisection::Point> points;
  for (const auto& part : all_gather(buf)) {
    Unpacker up{part};
    while (up.more()) points.push_back(up.get<Bisection::Point>());
  }
  std::sort(points.begin(), points.end(),
            [](const auto& p, const auto& q) { return p.slot < q.slot; });
  cuts_ = Bisection(std::move(points), size_);
  return true;
}

void MpiDomain::migrate(Exchange& ex, std::vector<Role>& roles) {
  // Bodies that left this region go to their new owner with their contact histories and
  // bonds (the new owner may not have evaluated the pairs they had with other ghosts).
  // (Bonds by slot made anew at each re-partition: a split moves bonds to its pieces and
  // re-sorts them.)
  const std::vector<std::vector<std::uint32_t>> bonds_of = ex.bonds_by_slot();
  std::vector<std::vector<char>> out(static_cast<std::size_t>(size_));
  for (std::uint32_t i = 0; i < ex.slots(); ++i) {
    if (!ex.owned(i)) continue;
    const int to = cuts_.owner(ex.state(i).x);
    if (to == rank_) {
      roles[i] = Role::owned;
      continue;
    }
    ++stats_.migrated;
    Packer pk{out[static_cast<std::size_t>(to)]};
    pk.put(i);
    pk.put(ex.state(i));
    const std::vector<HistoryEntry> histories = ex.histories_of(i);
    pk.put(static_cast<std::uint64_t>(histories.size()));
    for (const auto& e : histories) pk.put(e);
    pk.put(static_cast<std::uint64_t>(bonds_of[i].size()));
    for (const std::uint32_t k : bonds_of[i]) pk.put(ex.bond(k));
  }
  const auto in = all_to_all(out);
  std::vector<HistoryEntry> arrived;
  for (const auto& part : in) {
    Unpacker up{part};
    while (up.more()) {
      const auto i = up.get<std::uint32_t>();
      ex.set_state(i, up.get<BodyState>());
      roles[i] = Role::owned;
      up.each<HistoryEntry>([&](const auto& e) { arrived.push_back(e); });
      up.each<BondDynamic>([&](const BondDynamic& d) { ex.set_bond(d); });
    }
  }
  // Histories this process lacks join its list (one it has is the same, bit for bit).
  ex.merge_histories(std::move(arrived));
}

void MpiDomain::send_ghosts(Exchange& ex, std::vector<Role>& roles) {
  // Each owner sends the bodies within the halo of another process's region.
  const std::size_t slots = ex.slots();
  const auto n = static_cast<std::size_t>(size_);
  send_.assign(n, {});
  recv_.assign(n, {});
  std::vector<std::vector<char>> out(n);
  anchor_.resize(slots);
  for (std::uint32_t i = 0; i < slots; ++i) {
    if (roles[i] != Role::owned) continue;
    anchor_[i] = ex.state(i).x;
    for (int r = 0; r < size_; ++r) {
      if (r == rank_ || cuts_.distance(r, ex.state(i).x) > halo_) continue;
      send_[static_cast<std::size_t>(r)].push_back(i);
      Packer pk{out[static_cast<std::size_t>(r)]};
      pk.put(i);
      pk.put(ex.state(i));
    }
  }
  const auto in = all_to_all(out);
  for (std::size_t r = 0; r < n; ++r) {
    Unpacker up{in[r]};
    while (up.more()) {
      const auto i = up.get<std::uint32_t>();
      ex.set_state(i, up.get<BodyState>());
      roles[i] = Role::ghost;
      recv_[r].push_back(i);
    }
  }
}

void MpiDomain::exchange_ghost_states(World& world) {
  // The lists are fixed between re-partitions, so are the message sizes: one call.
  Exchange ex = world.exchange();
  const auto n = static_cast<std::size_t>(size_);
  constexpr int kState = static_cast<int>(Exchange::kStateBytes);
  std::vector<int> send_counts(n), recv_counts(n), send_at(n), recv_at(n);
  int sent = 0, received = 0;
  for (std::size_t r = 0; r < n; ++r) {
    send_counts[r] = kState * static_cast<int>(send_[r].size());
    recv_counts[r] = kState * static_cast<int>(recv_[r].size());
    send_at[r] = sent;
    recv_at[r] = received;
    sent += send_counts[r];
    received += recv_counts[r];
  }
  send_buffer_.resize(static_cast<std::size_t>(sent));
  recv_buffer_.resize(static_cast<std::size_t>(received));
  char* p = send_buffer_.data();
  for (std::size_t r = 0; r < n; ++r) {
    for (const std::uint32_t i : send_[r]) {
      ex.pack_state(i, p);
      p += Exchange::kStateBytes;
    }
  }
  {
    Timer timer(stats_.communication_seconds);
    MPI_Alltoallv(send_buffer_.data(), send_counts.data(), send_at.data(), MPI_BYTE, recv_buffer_.data(),
                  recv_counts.data(), recv_at.data(), MPI_BYTE, MPI_COMM_WORLD);
  }
  const std::uint64_t others = static_cast<std::uint64_t>(sent - send_counts[static_cast<std::size_t>(rank_)]);
  stats_.bytes_sent += others;
  stats_.ghost_bytes += others;
  const char* q = recv_buffer_.data();
  for (std::size_t r = 0; r < n; ++r) {
    for (const std::uint32_t i : recv_[r]) {
      ex.unpack_state(i, q);
      q += Exchange::kStateBytes;
    }
  }
  ++stats_.exchanges;
}

void MpiDomain::before_forces(World& world) {
  if (!attached_) throw std::logic_error("MpiDomain: attach the world first");
  // Some owned body has moved half the skin since the last re-partition (anywhere): the
  // ghosts may no longer hold every body that can touch an owned one.
  // A body that came or went (a split: every process made it) repartitions at once.
  Exchange ex = world.exchange();
  if (ex.take_bodies_changed()) {
    repartition(world, false);
    return;
  }
  bool moved = false;
  for (std::uint32_t i = 0; i < ex.slots() && !moved; ++i) {
    if (ex.owned(i)) moved = (ex.state(i).x - anchor_[i]).norm() >= 0.5 * skin_;
  }
  if (any(moved)) {
    repartition(world, false);
  } else {
    exchange_ghost_states(world);
  }
}

void MpiDomain::after_forces(World& world) {
  // The walls' reactions, summed as one process sums them (wall by wall, body by body, each
  // body's contacts in order), and this step's bond breaks, each from the owner of its A.
  Exchange ex = world.exchange();
  std::vector<char> buf;
  Packer pk{buf};
  const auto walls = ex.wall_forces();
  pk.put(static_cast<std::uint64_t>(walls.size()));
  for (const auto& w : walls) pk.put(w);
  for (const physics::BondBreak& br : ex.step_breaks()) {
    if (!world.owns(br.a)) continue;
    pk.put(br);
    pk.put(ex.bond(br.bond));
  }
  const auto in = all_gather(buf);
  std::vector<WallForceAt> forces;
  std::vector<std::pair<physics::BondBreak, BondDynamic>> breaks;
  for (const auto& part : in) {
    Unpacker up{part};
    up.each<WallForceAt>([&](const auto& f) { forces.push_back(f); });
    while (up.more()) {
      const auto br = up.get<physics::BondBreak>();
      breaks.emplace_back(br, up.get<BondDynamic>());
    }
  }
  std::sort(forces.begin(), forces.end(), [](const auto& p, const auto& q) {
    return std::tie(p.wall, p.slot, p.order) < std::tie(q.wall, q.slot, q.order);
  });
  ex.set_wall_reactions(forces);
  std::sort(breaks.begin(), breaks.end(), [](const auto& p, const auto& q) { return p.first.bond < q.first.bond; });
  std::vector<physics::BondBreak> all;
  for (const auto& [br, d] : breaks) {
    all.push_back(br);
    ex.set_bond(d);
  }
  ex.set_step_breaks(all);
}

void MpiDomain::gather_all(World& world, bool contacts) {
  Exchange ex = world.exchange();
  std::vector<char> buf;
  Packer pk{buf};
  std::uint64_t owned = 0, records = 0;
  for (std::uint32_t i = 0; i < ex.slots(); ++i) owned += ex.owned(i);
  pk.put(owned);
  for (std::uint32_t i = 0; i < ex.slots(); ++i) {
    if (ex.owned(i)) pk.put(OwnedState{i, ex.state(i)});
  }
  const std::vector<HistoryEntry> histories = ex.owned_histories();
  pk.put(static_cast<std::uint64_t>(histories.size()));
  for (const auto& e : histories) pk.put(e);
  const std::vector<physics::Bond>& bond_list = world.bonds();
  std::uint64_t bonds = 0;
  for (const auto& b : bond_list) bonds += world.owns(b.a);
  pk.put(bonds);
  for (std::size_t k = 0; k < bond_list.size(); ++k) {
    if (world.owns(bond_list[k].a)) pk.put(ex.bond(k));
  }
  if (contacts) {
    const auto& all = world.contacts();
    for (const auto& c : all) records += world.owns(c.wall ? c.b : c.a);
    pk.put(records);
    for (std::size_t k = 0; k < all.size(); ++k) {
      const auto& c = all[k];
      if (world.owns(c.wall ? c.b : c.a)) pk.put(RecordAt{c.wall ? 1u : 0u, c.a, c.b, k, c});
    }
  }
  const auto in = all_gather(buf);
  std::vector<HistoryEntry> history;
  std::vector<RecordAt> gathered;
  for (const auto& part : in) {
    Unpacker up{part};
    up.each<OwnedState>([&](const OwnedState& b) { ex.set_state(b.slot, b.state); });
    up.each<HistoryEntry>([&](const auto& e) { history.push_back(e); });
    up.each<BondDynamic>([&](const BondDynamic& d) { ex.set_bond(d); });
    if (contacts) up.each<RecordAt>([&](const RecordAt& r) { gathered.push_back(r); });
  }
  ex.set_histories(std::move(history));
  if (contacts) {
    // One process's order: the pairs sorted by (A, B), each pair's contacts as found, then
    // the walls' contacts wall by wall, body by body.
    std::stable_sort(gathered.begin(), gathered.end(), [](const RecordAt& p, const RecordAt& q) {
      return std::tie(p.group, p.first, p.second, p.order) < std::tie(q.group, q.first, q.second, q.order);
    });
    std::vector<physics::ContactRecord> records_in_order;
    for (const RecordAt& r : gathered) records_in_order.push_back(r.record);
    ex.set_records(std::move(records_in_order));
  }
}

double MpiDomain::sum(const physics::ExactSum& part) {
  Timer timer(stats_.communication_seconds);
  physics::ExactSum all = part;
  MPI_Allreduce(MPI_IN_PLACE, all.digits().data(), physics::ExactSum::kDigits, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, &all.special(), 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return all.value();
}

double MpiDomain::max(double part) {
  max(std::span<double>(&part, 1));
  return part;
}

void MpiDomain::max(std::span<double> parts) {
  Timer timer(stats_.communication_seconds);
  MPI_Allreduce(MPI_IN_PLACE, parts.data(), static_cast<int>(parts.size()), MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
}

std::uint64_t MpiDomain::count(std::uint64_t part) {
  Timer timer(stats_.communication_seconds);
  std::uint64_t all = 0;
  MPI_Allreduce(&part, &all, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
  return all;
}

bool MpiDomain::any(bool part) {
  Timer timer(stats_.communication_seconds);
  int mine = part ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return all != 0;
}

std::string MpiDomain::first(const std::optional<std::string>& mine) {
  int who = mine ? rank_ : size_, lowest = size_;
  {
    Timer timer(stats_.communication_seconds);
    MPI_Allreduce(&who, &lowest, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  }
  if (lowest == size_) return {};
  std::string text = lowest == rank_ ? *mine : std::string();
  int length = static_cast<int>(text.size());
  MPI_Bcast(&length, 1, MPI_INT, lowest, MPI_COMM_WORLD);
  text.resize(static_cast<std::size_t>(length));
  MPI_Bcast(text.data(), length, MPI_CHAR, lowest, MPI_COMM_WORLD);
  return text;
}

std::vector<DomainStats> MpiDomain::all_stats() {
  std::vector<char> buf;
  Packer{buf}.put(stats_);
  std::vector<DomainStats> all;
  for (const auto& part : all_gather(buf)) all.push_back(Unpacker{part}.get<DomainStats>());
  return all;
}

}  // namespace cleave::parallel

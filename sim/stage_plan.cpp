#include "sim/stage_plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace cleave::sim {

using io::StageDef;

void put_summary(physics::StateWriter& w, const StageSummary& st) {
  w.put(st.name);
  w.put(st.kind);
  w.put(st.steps);
  w.put(st.start);
  w.put(st.end);
  w.put(st.ended_by);
  w.put(st.event_missed);
  w.put(st.peak_load);
  w.put(st.peak_displacement);
  w.put<std::uint64_t>(st.bonds_broken);
  w.put<std::uint64_t>(st.splits);
  w.put(st.plot);
  for (const CrackTotals* c : {&st.cracks_start, &st.cracks_end, &st.cracks_at_peak})
    put_totals(w, *c);
}

StageSummary get_summary(physics::StateReader& r) {
  StageSummary st;
  st.name = r.string();
  st.kind = r.get_enum(StageDef::Kind::bond);
  st.steps = r.get<std::uint64_t>();
  st.start = r.get<double>();
  st.end = r.get<double>();
  st.ended_by = r.string();
  st.event_missed = r.get_bool();
  st.peak_load = r.get<double>();
  st.peak_displacement = r.get<double>();
  st.bonds_broken = r.get<std::uint64_t>();
  st.splits = r.get<std::uint64_t>();
  st.plot = r.string();
  for (CrackTotals* c : {&st.cracks_start, &st.cracks_end, &st.cracks_at_peak}) *c = get_totals(r);
  return st;
}

void put_progress(physics::StateWriter& w, const StageProgress& p) {
  put_summary(w, p.st);
  w.put<std::uint64_t>(p.breaks0);
  w.put(p.stage_origin);
  w.put(p.plot_x);
  w.put(p.plot_y);
  w.put(p.event);
}

StageProgress get_progress(physics::StateReader& r) {
  StageProgress p;
  p.st = get_summary(r);
  p.breaks0 = r.get<std::uint64_t>();
  p.stage_origin = r.vec3s();
  p.plot_x = r.numbers<double>();
  p.plot_y = r.numbers<double>();
  p.event = r.get_bool();
  return p;
}

StageDef plain_stage(const io::Scenario& scenario, const physics::World& world) {
  StageDef plain;
  plain.name = "run";
  plain.steps =
      static_cast<std::uint64_t>(std::ceil(scenario.dynamics.duration / world.settings().dt));
  plain.frames = scenario.dynamics.frames;
  for (const physics::Wall& w : world.walls()) plain.wall_velocity.emplace_back(w.name, w.velocity);
  return plain;
}

void StageRun::plan(const physics::World& world, std::uint64_t max_steps) {
  limit = stage->steps > 0
              ? stage->steps
              : static_cast<std::uint64_t>(std::ceil(stage->time / world.settings().dt));
  if (max_steps > 0) {
    const std::uint64_t started_at = world.steps() - progress.st.steps;  // the stage's first step
    const std::uint64_t left = max_steps > started_at ? max_steps - started_at : 0;
    if (left < limit) {
      limit = left;
      capped = true;  // the run ends with this stage unless its event comes first
    }
  }
  frame_every = stage->frames > 0 ? std::max<std::uint64_t>(1, limit / stage->frames) : 0;
  log_every = std::max<std::uint64_t>(1, limit / 1000);
  t0 = std::chrono::steady_clock::now();
  i = progress.st.steps + 1;  // 1, or the step after the checkpoint
}

bool stage_event(const StageRun& r, const physics::World& world, const StageReadings& now) {
  const StageSummary& st = r.progress.st;
  switch (r.stage->until) {
    case StageDef::Until::limit:
      return r.plain && now.settled;
    case StageDef::Until::all_in_contact:
      return now.all_in_contact;
    case StageDef::Until::walls_touch:
      return std::all_of(r.load_walls.begin(), r.load_walls.end(), [&](std::size_t w) {
        return world.walls()[w].reaction.squaredNorm() > 0.0;
      });
    case StageDef::Until::load_drop:
      // After the peak, once bonds have broken or grains split (or there are no bonds to
      // break): load that eases off before anything has broken (a rig settling) does not
      // end a test. A crack may run through grains alone (transgranular fracture on,
      // strong bonds): its splits count as the fracture that ends the test.
      return st.peak_load > 0.0 && now.load < r.stage->load_drop * st.peak_load &&
             (now.broken > 0 || st.splits > 0 || world.bonds().empty());
  }
  return false;
}

bool all_in_contact(const physics::World& world, std::vector<char>& touched) {
  touched.clear();
  for (const auto& c : world.contacts()) {
    if (c.wall || c.overlap <= 0.0) continue;
    const std::size_t top = std::max(c.a, c.b) + 1;
    if (touched.size() < top) touched.resize(top, 0);
    touched[c.a] = touched[c.b] = 1;
  }
  bool all = true;
  for (const physics::BodyId id : world.body_ids()) {
    if (!world.owns(id.index)) continue;  // one process of several answers for its own bodies
    if (id.index >= touched.size() || !touched[id.index]) {
      all = false;
      break;
    }
  }
  physics::Domain* domain = world.domain();
  return domain ? !domain->any(!all) : all;
}

namespace {

/// The progress line's ETA: the time left to the stage's step limit when the limit ends it;
/// an upper bound when settling may end a plain run sooner; none when an event (a load drop, walls
/// touching) ends it, since its time limit says nothing about when that comes.
std::string eta_text(const StageDef& stage, bool may_settle, double seconds_left) {
  if (may_settle) return fmt::format("  ETA <= {:.0f} s   ", seconds_left);
  if (stage.until == StageDef::Until::limit) return fmt::format("  ETA {:.0f} s   ", seconds_left);
  return fmt::format("  until {}   ", io::to_string(stage.until));
}

}  // namespace

std::string progress_line(const StageRun& r, const physics::World& world, std::size_t contacts,
                          double kinetic, std::size_t splits, bool fracture, double load,
                          bool may_settle) {
  const std::uint64_t i = r.i - 1;  // the step just taken
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - r.t0).count();
  const double left = elapsed / static_cast<double>(i) * static_cast<double>(r.limit - i);
  std::string line =
      fmt::format("\r  stage {:<12} step {}/{}  t = {:.4g} s  bodies {}  contacts {}  KE {:.3g} J",
                  r.stage->name, i, r.limit, world.time(), world.body_count(), contacts, kinetic);
  if (!world.bonds().empty()) {
    line += fmt::format("  bonds {}/{} broken", world.bond_counts().broken(), world.bonds().size());
  }
  if (fracture) line += fmt::format("  splits {}", splits);
  if (!r.load_walls.empty()) line += fmt::format("  load {:.4g} N", load);
  line += eta_text(*r.stage, may_settle, left);
  return line;
}

}  // namespace cleave::sim

// The pile of a centrifuge run as it is recorded: see pile_recorder.hpp.
#include "pilempm/scenario/centrifuge/pile_recorder.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <sstream>

#include "pilempm/core/error.hpp"
#include "pilempm/core/number_text.hpp"

namespace pilempm::scenario {

using simulation::MpmPhase;
using simulation::MpmPhaseRole;
using simulation::PilePart;

namespace {

double pile_y(const mpm::MpmState& solver) {
  return solver.rigid_body(0).displacement().y();
}

}  // namespace

PileRecorder::PileRecorder(const CentrifugeScenario& s, double factor)
    : s_(s), factor_(factor), interval_(s.record_interval_D * s.pile_diameter) {}

void PileRecorder::run_start(const simulation::Scheme& scheme, std::size_t first_phase) {
  if (first_phase == 0) return;
  const mpm::MpmState& solver = scheme.state();
  last_row_y_ = phase_start_y_ = pile_y(solver);
  last_reaction_ = solver.boundary_reaction();
  momentum_ = factor_ * solver.vertical_momentum();
  if (!rows_.empty()) soil_weight_ = rows_.back().soil_weight;
}

namespace {

// The numbers of a row in the order of PileRecorder::saved().
std::vector<double*> row_numbers(PileRow& r) {
  return {&r.time,      &r.displacement,  &r.phase_displacement,
          &r.tip_depth, &r.head,          &r.tip,
          &r.shaft,     &r.base_reaction, &r.soil_weight,
          &r.kinetic,   &r.pile_work,     &r.momentum_rate,
          &r.damping};
}

}  // namespace

std::string PileRecorder::saved() const {
  std::string text;
  for (PileRow row : rows_) {
    text += fmt::format("{}\t{}", row.phase, static_cast<int>(row.role));
    for (const double* v : row_numbers(row)) text += fmt::format("\t{:.17g}", *v);
    text += '\n';
  }
  return text;
}

void PileRecorder::restore(const std::string& saved) {
  std::vector<PileRow> rows;
  std::istringstream lines(saved);
  std::string line;
  while (std::getline(lines, line)) {
    // phase, role, then the numbers, separated by tabs ("nan" and "inf" read as numbers too).
    std::vector<std::string> fields;
    std::istringstream parts(line);
    for (std::string field; std::getline(parts, field, '\t');) fields.push_back(field);
    PileRow row;
    std::vector<double*> numbers = row_numbers(row);
    bool ok = fields.size() == numbers.size() + 2 && !fields[0].empty();
    for (std::size_t k = 1; ok && k < fields.size(); ++k) {
      const std::optional<double> value = whole_number(fields[k]);
      ok = value.has_value();
      if (!ok) break;
      if (k == 1)
        row.role = static_cast<MpmPhaseRole>(static_cast<int>(*value));
      else
        *numbers[k - 2] = *value;
    }
    if (!ok)
      throw Error(fmt::format("the pile's rows of a checkpoint: line {} cannot be read: {}",
                              rows.size() + 1, line));
    row.phase = fields[0];
    rows.push_back(std::move(row));
  }
  rows_ = std::move(rows);
}

void PileRecorder::after_step(const simulation::Scheme& scheme, const MpmPhase& phase, double dt) {
  const mpm::MpmState& solver = scheme.state();
  // With inertia a row shows the means since the last row; without, the values at its time.
  const double weight = scheme.inertial() ? dt : 0.0;
  if (scheme.inertial()) means_.add_step(solver, dt);
  reaction_impulse_ += weight * solver.boundary_reaction();
  damping_impulse_ += weight * solver.damping_force();
  elapsed_ += weight;
  last_reaction_ = solver.boundary_reaction();
  stepped_ = true;
  // Installation: a row per record interval; the short relaxation and load test: ten.
  const double interval = phase.role == MpmPhaseRole::installation ? interval_ : 0.1 * interval_;
  if (phase.role != MpmPhaseRole::initial_stress &&
      std::abs(pile_y(solver) - last_row_y_) >= interval * (1.0 - 1e-9))
    add_row(solver, phase);
}

void PileRecorder::phase_end(const simulation::Scheme& scheme, const MpmPhase& phase) {
  if (stepped_) add_row(scheme.state(), phase);
  phase_start_y_ = pile_y(scheme.state());
}

void PileRecorder::add_row(const mpm::MpmState& solver, const MpmPhase& phase) {
  const std::vector<mpm::RigidBodyForce> forces = means_.take(solver);
  const mpm::RigidBodyForce& f = forces.at(0);
  const auto tip = static_cast<std::size_t>(PilePart::tip);
  const auto shaft = static_cast<std::size_t>(PilePart::shaft);
  PileRow row;
  row.time = solver.time();
  row.phase = phase.name;
  row.role = phase.role;
  const double y = pile_y(solver);
  row.displacement = 0.0 - y;  // 0 - y: no "-0" in the file
  row.phase_displacement = 0.0 - (y - phase_start_y_);
  row.tip_depth = s_.wished_in_place_D * s_.pile_diameter - y;
  row.head = factor_ * f.total.y();
  row.tip = f.parts.size() > tip ? factor_ * f.parts[tip].y() : 0.0;
  row.shaft = f.parts.size() > shaft ? factor_ * f.parts[shaft].y() : 0.0;
  row.base_reaction =
      factor_ * (elapsed_ > 0.0 ? reaction_impulse_.y() / elapsed_ : last_reaction_.y());
  row.damping = elapsed_ > 0.0 ? factor_ * damping_impulse_.y() / elapsed_ : 0.0;
  if (!soil_weight_) {  // the particles and their masses do not change
    double mass = 0.0;
    for (double m : solver.particles().mass) mass += m;
    soil_weight_ = factor_ * mass * s_.gravity * s_.g_level;
  }
  row.soil_weight = *soil_weight_;
  row.kinetic = factor_ * solver.energies().kinetic;
  row.pile_work = factor_ * solver.energies().contact_work;
  // The sand's vertical momentum with the inertial (scaled) mass; it starts at rest at t = 0.
  const double momentum = factor_ * solver.vertical_momentum();
  row.momentum_rate = elapsed_ > 0.0 ? (momentum - momentum_) / elapsed_ : 0.0;
  momentum_ = momentum;
  rows_.push_back(row);
  reaction_impulse_ = damping_impulse_ = mpm::Vec2::Zero();
  elapsed_ = 0.0;
  stepped_ = false;
  last_row_y_ = y;
}

}  // namespace pilempm::scenario

// What a centrifuge run measured: see experiment.hpp.
#include "pilempm/scenario/centrifuge/experiment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "pilempm/core/tensor.hpp"
#include "pilempm/mpm/quasi_static/load_path.hpp"

namespace pilempm::scenario {

using simulation::MpmPhase;
using simulation::MpmPhaseRole;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The largest |Σ quantity Δu| / Σ head Δu over consecutive windows of `window` of pile travel u
// during installation, among the windows whose mean head force exceeds `threshold` (NaN if none).
template <class Quantity>
double max_window_ratio(const std::vector<PileRow>& rows, double window, double threshold,
                        const Quantity& quantity) {
  double worst = kNaN, head = 0.0, sum = 0.0, travel = 0.0, previous = 0.0;
  for (const PileRow& r : rows) {
    if (r.role != MpmPhaseRole::installation) continue;
    const double step = r.displacement - previous;
    previous = r.displacement;
    if (step <= 0.0) continue;
    head += r.head * step;
    sum += quantity(r) * step;
    travel += step;
    if (travel < window * (1.0 - 1e-6)) continue;
    const double ratio = std::abs(sum) / head;
    if (head / travel > threshold && !(ratio <= worst)) worst = ratio;  // NaN: the first window
    head = sum = travel = 0.0;
  }
  return worst;
}

}  // namespace

double head_force_scatter(const std::vector<double>& travel, const std::vector<double>& head) {
  if (travel.size() != head.size() || travel.size() < 5) return kNaN;
  double sum = 0.0;
  for (double f : head) sum += f;
  if (!(sum > 0.0)) return kNaN;
  return mpm::quasi_static::scatter_about_fit(travel, head, 2);
}

void initial_stress_check(const CentrifugeScenario& s, const mpm::MpmState& solver,
                          CentrifugeSummary& summary) {
  const double unit = s.sand_density() * s.g_level * s.gravity;  // [Pa/m]
  const double H = s.sand_height();
  double worst = 0.0, ratio_sum = 0.0;
  long count = 0;
  const mpm::Particles& particles = solver.particles();
  for (std::size_t p = 0; p < particles.size(); ++p) {
    if (particles.position[p].x() < 2.0 * s.pile_diameter) continue;
    const double z = H - particles.position[p].y();
    const double sigma_v = -particles.state[p].stress[k22];
    worst = std::max(worst, std::abs(sigma_v - unit * z) / (unit * H));
    if (z > s.pile_diameter) {
      ratio_sum += sigma_v / (unit * z);
      ++count;
    }
  }
  summary.initial_stress_error = worst;
  summary.initial_stress_ratio = count > 0 ? ratio_sum / static_cast<double>(count) : kNaN;
}

CentrifugeChecks::CentrifugeChecks(const CentrifugeScenario& s, CentrifugeSummary& summary)
    : s_(s), summary_(summary) {
  summary_.min_radius_mm = kNaN;
}

void CentrifugeChecks::phase_end(const simulation::Scheme& scheme, const MpmPhase& phase) {
  const mpm::MpmState& solver = scheme.state();
  // No particle passes through the pile, none crosses the axis.
  std::size_t inside = 0;
  double min_radius = std::numeric_limits<double>::infinity();
  const double cell = s_.pile_diameter / s_.cells_per_D;
  for (const mpm::Vec2& x : solver.particles().position) {
    const double distance = solver.rigid_body(0).signed_distance(x);
    if (distance < -cell) ++inside;
    summary_.max_penetration_cells = std::max(summary_.max_penetration_cells, -distance / cell);
    min_radius = std::min(min_radius, x.x());
  }
  summary_.particles_in_pile = std::max(summary_.particles_in_pile, inside);
  if (!(1e3 * min_radius >= summary_.min_radius_mm)) summary_.min_radius_mm = 1e3 * min_radius;
  if (phase.role == MpmPhaseRole::initial_stress) {
    initial_stress_check(s_, solver, summary_);
    summary_.particles = solver.particles().size();
  }
}

void summarise_pile(const CentrifugeScenario& s, const std::vector<PileRow>& rows,
                    CentrifugeSummary& summary) {
  const double D = s.pile_diameter;
  // The figures of the summary.
  summary.installation_head_force = summary.installation_tip_depth_D = kNaN;
  summary.peak_tip_stress_MPa = summary.peak_tip_stress_depth_D = kNaN;
  summary.relaxation_travel_mm = summary.capacity = summary.load_test_displacement_mm = kNaN;
  summary.equilibrium_error = summary.equilibrium_error_1D = summary.equilibrium_closure = kNaN;
  summary.max_kinetic_to_work = kNaN;
  summary.scatter_last_D = summary.largest_scatter = summary.largest_scatter_from_D = kNaN;
  const double tip_area = std::numbers::pi * 0.25 * D * D;
  const double cell = D / s.cells_per_D;
  double end_displacement = 0.0;
  for (const PileRow& r : rows)
    if (r.role == MpmPhaseRole::installation) end_displacement = r.displacement;
  double sum = 0.0, weight = 0.0, last_displacement = -1.0;
  for (const PileRow& r : rows) {
    if (r.role == MpmPhaseRole::installation) {
      const double stress = r.tip / tip_area / 1e6;
      if (!(stress <= summary.peak_tip_stress_MPa)) {
        summary.peak_tip_stress_MPa = stress;
        summary.peak_tip_stress_depth_D = r.tip_depth / D;
      }
      const double travel = r.displacement - std::max(last_displacement, 0.0);
      if (r.displacement >= end_displacement - cell - 1e-12 && travel > 0.0) {
        sum += r.head * travel;
        weight += travel;
      }
      if (r.pile_work > 0.0 && r.displacement >= D)
        summary.max_kinetic_to_work =
            std::max(std::isfinite(summary.max_kinetic_to_work) ? summary.max_kinetic_to_work : 0.0,
                     r.kinetic / r.pile_work);
      last_displacement = r.displacement;
      summary.installation_tip_depth_D = r.tip_depth / D;
    }
    if (r.role == MpmPhaseRole::relaxation)
      summary.relaxation_travel_mm = -1e3 * r.phase_displacement;
    if (r.role == MpmPhaseRole::load_test) {
      summary.capacity = r.head;
      summary.load_test_displacement_mm = 1e3 * r.phase_displacement;
    }
  }
  if (weight > 0.0) summary.installation_head_force = sum / weight;
  if (std::isfinite(summary.installation_head_force)) {
    const auto residual = [](const PileRow& r) { return r.equilibrium_residual(); };
    const double threshold = 0.5 * summary.installation_head_force;
    summary.equilibrium_error = max_window_ratio(rows, cell, threshold, residual);
    summary.equilibrium_error_1D = max_window_ratio(rows, D, threshold, residual);
    summary.equilibrium_closure = max_window_ratio(
        rows, cell, threshold, [](const PileRow& r) { return r.force_book_closure(); });
  }
  // The head force's scatter over D of travel: the last D, and each D from the start (rows on
  // a window's edge belong to both windows).
  std::vector<double> travel, head;
  for (const PileRow& r : rows)
    if (r.role == MpmPhaseRole::installation) {
      travel.push_back(r.displacement / D);
      head.push_back(r.head);
    }
  if (travel.empty() || !(travel.back() >= 1.0 - 1e-9)) return;
  const auto scatter_over = [&](double from, double to) {
    std::vector<double> x, f;
    for (std::size_t i = 0; i < travel.size(); ++i)
      if (travel[i] >= from - 1e-9 && travel[i] <= to + 1e-9) {
        x.push_back(travel[i]);
        f.push_back(head[i]);
      }
    return head_force_scatter(x, f);
  };
  // The whole D from the start, and the last D where the travel is not a whole number of D:
  // the last window is always the last D.
  const double end = travel.back();
  std::vector<double> starts;
  for (int k = 0; k + 1 <= end + 1e-9; ++k) starts.push_back(k);
  if (end - 1.0 > starts.back() + 1e-9) starts.push_back(end - 1.0);
  for (const double from : starts) {
    const double scatter = scatter_over(from, from + 1.0);
    if (from == starts.back()) summary.scatter_last_D = scatter;
    if (std::isnan(scatter) || scatter <= summary.largest_scatter) continue;
    summary.largest_scatter = scatter;
    summary.largest_scatter_from_D = from;
  }
}

}  // namespace pilempm::scenario

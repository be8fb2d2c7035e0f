// The quasi-static solver's run state for checkpoints: what a restart needs beyond the particles
// (contact points and their history, the last step's nodal displacements, the load multipliers
// and the fixed contact moduli).
#include <fmt/format.h>

#include <algorithm>

#include "pilempm/core/error.hpp"
#include "pilempm/mpm/quasi_static/step_data.hpp"

namespace pilempm::mpm::quasi_static {

using namespace detail;

namespace {

constexpr const char* kCornerPositions = "contact_corner_position_m";
constexpr const char* kCornerForces = "contact_tangential_force_N";
constexpr const char* kCornerBodies = "contact_body";
constexpr const char* kNodeDisplacements = "last_node_displacement_m";
// gravity multiplier, traction multiplier, last body step [m], largest penetration [m],
// boundary reaction x, y [N] (the work account is the run state's energies)
constexpr const char* kLoad = "quasi_static_load";
constexpr const char* kContactModulus = "contact_modulus_Pa";  // per material (0: not fixed)
// The low-stress stabilisation's reference (only with the stabilisation, once a body moved):
// each particle's strain increment (6 components) and the body motion it went with [m].
constexpr const char* kReferenceStrain = "low_stress_reference_strain";
constexpr const char* kReferenceMotion = "low_stress_reference_motion_m";

std::vector<double> flat(const std::vector<Vec2>& v) {
  std::vector<double> out;
  out.reserve(2 * v.size());
  for (const Vec2& x : v) {
    out.push_back(x.x());
    out.push_back(x.y());
  }
  return out;
}

}  // namespace

SolverRunState QuasiStaticSolver::run_state() const {
  SolverRunState state;
  state.time = time_;
  state.steps = steps_;
  state.energies = energies_;
  state.rigid_body_forces = body_forces_;
  std::vector<double> forces, bodies;
  for (const ContactHistory& h : contact_history_) {
    forces.push_back(h.tangential_force.x());
    forces.push_back(h.tangential_force.y());
    bodies.push_back(h.body);
  }
  state.scheme_arrays = {{kCornerPositions, flat(corner_position_)},
                         {kCornerForces, std::move(forces)},
                         {kCornerBodies, std::move(bodies)},
                         {kNodeDisplacements, flat(node_displacement_)},
                         {kLoad,
                          {gravity_multiplier_, traction_multiplier_, last_body_step_,
                           max_penetration_, boundary_reaction_.x(), boundary_reaction_.y()}},
                         {kContactModulus, contact_modulus_}};
  if (!reference_strain_.empty()) {
    std::vector<double> strains;
    strains.reserve(6 * reference_strain_.size());
    for (const Vec6& e : reference_strain_) strains.insert(strains.end(), e.data(), e.data() + 6);
    state.scheme_arrays.push_back({kReferenceStrain, std::move(strains)});
    state.scheme_arrays.push_back(
        {kReferenceMotion, {reference_motion_.x(), reference_motion_.y()}});
  }
  return state;
}

void QuasiStaticSolver::restore_run_state(const SolverRunState& state) {
  // An array of the given size, or nullptr where the state has none by that name.
  auto optional_array = [&](const char* name, std::size_t size) -> const std::vector<double>* {
    for (const auto& [key, values] : state.scheme_arrays)
      if (key == name) {
        if (values.size() != size)
          throw InvalidValue(fmt::format("quasi-static run state {}", name),
                             std::to_string(values.size()), std::to_string(size));
        return &values;
      }
    return nullptr;
  };
  auto array = [&](const char* name, std::size_t size) -> const std::vector<double>& {
    if (const std::vector<double>* values = optional_array(name, size)) return *values;
    throw InvalidValue("quasi-static run state", "no array " + std::string(name),
                       "the arrays of a quasi-static checkpoint");
  };
  const std::size_t corners = particles_.size() * kCorners;
  const std::size_t nodes = std::size_t(grid_.node_count());
  if (state.rigid_body_forces.size() != bodies_.size())
    throw InvalidValue("rigid body forces in the run state",
                       std::to_string(state.rigid_body_forces.size()),
                       fmt::format("{} (one per rigid body)", bodies_.size()));
  const std::vector<double>& positions = array(kCornerPositions, 2 * corners);
  const std::vector<double>& forces = array(kCornerForces, 2 * corners);
  const std::vector<double>& bodies = array(kCornerBodies, corners);
  const std::vector<double>& displacements = array(kNodeDisplacements, 2 * nodes);
  const std::vector<double>& load = array(kLoad, 6);
  contact_modulus_ = array(kContactModulus, materials_.size());
  contact_history_.assign(corners, ContactHistory{});
  corner_position_.resize(corners);
  for (std::size_t c = 0; c < corners; ++c) {
    corner_position_[c] = Vec2(positions[2 * c], positions[2 * c + 1]);
    contact_history_[c].tangential_force = Vec2(forces[2 * c], forces[2 * c + 1]);
    contact_history_[c].body = static_cast<int>(bodies[c]);
  }
  node_displacement_.resize(nodes);
  for (std::size_t n = 0; n < nodes; ++n)
    node_displacement_[n] = Vec2(displacements[2 * n], displacements[2 * n + 1]);
  gravity_multiplier_ = load[0];
  traction_multiplier_ = load[1];
  last_body_step_ = load[2];
  max_penetration_ = load[3];
  boundary_reaction_ = Vec2(load[4], load[5]);
  // Without the reference (a run without the stabilisation, or before any body moved) the
  // stabilisation's first sub-increment after the restart resists the whole increment.
  const std::vector<double>* strains = optional_array(kReferenceStrain, 6 * particles_.size());
  const std::vector<double>* motion = optional_array(kReferenceMotion, 2);
  reference_strain_.clear();
  reference_motion_ = Vec2::Zero();
  if (strains != nullptr && motion != nullptr) {
    reference_strain_.resize(particles_.size());
    for (std::size_t i = 0; i < particles_.size(); ++i)
      reference_strain_[i] = Eigen::Map<const Vec6>(strains->data() + 6 * i);
    reference_motion_ = Vec2((*motion)[0], (*motion)[1]);
  }
  energies_ = state.energies;
  body_forces_ = state.rigid_body_forces;
  time_ = state.time;
  steps_ = state.steps;
}

}  // namespace pilempm::mpm::quasi_static

#pragma once
// Objective (Jaumann) rotation of a point's tensorial state over one step.
#include <span>

#include "pilempm/constitutive/material_state.hpp"

namespace pilempm {

/// Rotation matrix of the Hughes & Winget (1980) midpoint rule, R = (I - W/2)^-1 (I + W/2), for
/// the spin increment W = skew(grad v) dt. Exactly orthogonal for any W.
Mat3 hughes_winget_rotation(const Mat3& spin_increment);

/// Rotates the stress and the history tensors among `history` (a model's
/// history_variables()) of a state by the spin increment, the objective part of a Jaumann-rate
/// update. Call before ConstitutiveModel::update.
void rotate_state(MaterialState& state, const Mat3& spin_increment,
                  std::span<const HistoryVariable> history);

}  // namespace pilempm

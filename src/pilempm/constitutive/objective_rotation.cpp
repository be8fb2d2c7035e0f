#include "pilempm/constitutive/objective_rotation.hpp"

#include "pilempm/constitutive/constitutive_model.hpp"

namespace pilempm {

Mat3 hughes_winget_rotation(const Mat3& spin_increment) {
  const Mat3 identity = Mat3::Identity();
  return (identity - 0.5 * spin_increment).inverse() * (identity + 0.5 * spin_increment);
}

void rotate_state(MaterialState& state, const Mat3& spin_increment,
                  std::span<const HistoryVariable> history) {
  const Mat3 rotation = hughes_winget_rotation(spin_increment);
  state.stress = rotate(state.stress, rotation);
  rotate_history_tensors(history, state, [&](Vec6& tensor) { tensor = rotate(tensor, rotation); });
}

}  // namespace pilempm

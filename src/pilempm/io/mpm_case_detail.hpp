#pragma once
// Pieces of the MPM case reader (io/mpm_case.hpp) shared by its files: mpm_case.cpp reads the
// case, mpm_case_phase.cpp its [[phase]] tables.
#include <string>
#include <vector>

#include "pilempm/core/number_range.hpp"
#include "pilempm/io/material_reader.hpp"
#include "pilempm/io/toml_reader.hpp"
#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm::mpm_case_detail {

// Speeds (initial particle velocities, prescribed body velocities): 10 km/s is beyond anything
// this program models, and the time step must stay finite (the wave speed adds to it).
inline const NumberRange kVelocityRange = NumberRange::closed(-1.0e4, 1.0e4);

// Names as a list for messages: "a", "b".
std::string quoted_names(const std::vector<std::string>& names);

// One [[phase]] table (the phase number `index` from 0), given the case read so far: its regions,
// bodies and solver settings.
simulation::MpmPhase read_phase(TableReader& t, const simulation::MpmCase& c,
                                const MaterialCatalog& catalog, int index);

}  // namespace pilempm::mpm_case_detail

#pragma once
// MPM case files (docs/mpm-case-files.md): the geometry, the background grid and its boundary
// conditions (absorbing ones included), the solver settings, the materials ([[material]] tables
// read as in element case files), rectangular regions filled with particles and their initial
// state, rigid bodies, surface tractions, and the list of phases with their body motions, stop
// rules and material changes. Reading is strict: an unknown key or a bad value is an InputError
// with the file, the line, the key, the value and the allowed range. Everything returned is SI.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm {

/// Reads a case file (throws InputError).
simulation::MpmCase read_mpm_case(const std::filesystem::path& path);
/// Reads case text; `source_name` is what messages call the file.
simulation::MpmCase read_mpm_case_text(std::string_view text, const std::string& source_name);

}  // namespace pilempm

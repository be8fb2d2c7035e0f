#pragma once
// Writing MPM case files (docs/mpm-case-files.md) from the typed case: the file a scenario writes
// for the record (mpm_case.toml), which `pilempm mpm run` runs. Read back by io/mpm_case.hpp it is
// the same case, field by field and to the last bit: every number is written as the shortest
// decimal that the reader turns into the same double (through its unit: kPa, degrees, tan δ).
// What is not a case-file key is not written: where the case came from (its file, lines and
// keys), and the models, which the reader builds again from the materials.
#include <filesystem>
#include <string>
#include <vector>

#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm {

/// The case file text of `c`, after the `comments` (one "# " line each). Throws Error when the
/// case cannot be written as a file: grid nodes that are not those of its axes, a material of a
/// model without a parameter writer, a traction on a region whose name is not unique, two stop
/// rules of the same key, a side that is both fixed and absorbing.
std::string mpm_case_text(const simulation::MpmCase& c,
                          const std::vector<std::string>& comments = {});

/// Writes mpm_case_text to `file` atomically (io/output/atomic_file.hpp).
void write_mpm_case(const std::filesystem::path& file, const simulation::MpmCase& c,
                    const std::vector<std::string>& comments = {});

}  // namespace pilempm

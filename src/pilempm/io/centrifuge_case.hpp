#pragma once
// Centrifuge case files (docs/centrifuge.md): the centrifuge pile test of docs/study.md §4 given by
// its physics ([test], [sand], [pile], [installation], [relaxation], [load_test], [mesh], [solver],
// [output], and [[material]] / [integrator] tables as in element case files). Reading is strict:
// unknown keys and bad values are InputErrors with the file, the line, the key, the value and the
// allowed range. Every key has the default of docs/study.md §4.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "pilempm/scenario/centrifuge/centrifuge_scenario.hpp"
#include "pilempm/simulation/mpm_case.hpp"

namespace pilempm {

/// Reads a centrifuge case file (throws InputError). `analysis`, when given (the command line's
/// `--analysis`), is the analysis the case runs whatever its `[solver] analysis` says (that key
/// is still checked); the keys of the other analysis are then errors as they are for the file's.
scenario::CentrifugeScenario read_centrifuge_case(
    const std::filesystem::path& path,
    std::optional<simulation::MpmAnalysis> analysis = std::nullopt);
/// Reads centrifuge case text; `source_name` is what messages call the file; `analysis` as above.
scenario::CentrifugeScenario read_centrifuge_case_text(
    std::string_view text, const std::string& source_name,
    std::optional<simulation::MpmAnalysis> analysis = std::nullopt);

/// The MPM case file text of a scenario's typed case (scenario::centrifuge_case), as
/// `centrifuge run` writes it for the record (mpm_case.toml) and `centrifuge case` prints it.
std::string centrifuge_mpm_case_text(const simulation::MpmCase& c);

/// The MPM case of a scenario as `pilempm mpm run` reads it from that text (so with the checks
/// of the case-file reader); `source_name` names it in messages. Throws InputError.
simulation::MpmCase centrifuge_to_mpm_case(const scenario::CentrifugeScenario& scenario,
                                           const std::string& source_name);

}  // namespace pilempm

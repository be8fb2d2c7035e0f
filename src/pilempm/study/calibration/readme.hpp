#pragma once
// DIR/README.md of the calibration study: the run, the items with their initial void-ratio
// convention and files, each item's section, the files and how to draw the figures again.
#include <string>
#include <vector>

#include "pilempm/study/calibration_study.hpp"

namespace pilempm::study::calibration {

/// How to draw the figures again, run in the output folder.
std::string plot_command();

/// README.md of a study run; `bodies` holds each item's section (in the order of report.items).
std::string study_readme(const CalibrationStudyReport& report,
                         const std::vector<std::string>& bodies);

}  // namespace pilempm::study::calibration

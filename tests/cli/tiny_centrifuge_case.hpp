#pragma once
// A tiny quasi-static centrifuge case for the command-line tests of restarts and of the study's
// continued runs: R = 4 D, H = 6 D, D/2 cells, the pile wished in place at 2 D and jacked 0.5 D,
// relaxation, a 0.05 D load test, one thread (173 particles, about a second).
#include <string>

namespace pilempm_test {

/// The case with `sand` the lines of its [sand] table (material, e0, ...).
inline std::string tiny_centrifuge_case(const std::string& title, const std::string& sand) {
  std::string text = "title = \"" + title + "\"\n\n";
  text += "[test]\ncontainer_radius_D = 4.0\nsand_height_D = 6.0\n\n";
  text += "[sand]\ne0_at = \"initial-stress\"\n" + sand + "\n";
  text += "[solver]\nanalysis = \"quasi-static\"\nthreads = 1\n\n";
  text += "[installation]\nwished_in_place_D = 2.0\ndepth_D = 0.5\n\n";
  text += "[load_test]\ndisplacement_D = 0.05\n\n";
  text += "[mesh]\ncells_per_D = 2\nfine_radius_D = 2.0\nfine_depth_below_tip_D = 2.0\n";
  text += "headroom_D = 1.0\n";
  return text;
}

/// A run's summary.csv with its wall time (the third column) blanked: what two runs of one case
/// share.
inline std::string summary_without_wall_time(const std::string& csv) {
  std::string out;
  std::size_t start = 0;
  while (start < csv.size()) {
    std::size_t end = csv.find('\n', start);
    if (end == std::string::npos) end = csv.size();
    std::string line = csv.substr(start, end - start);
    const std::size_t first = line.find(',');
    const std::size_t second = line.find(',', first + 1);
    const std::size_t third = line.find(',', second + 1);
    if (third != std::string::npos) line.replace(second + 1, third - second - 1, "(wall)");
    out += line + "\n";
    start = end + 1;
  }
  return out;
}

}  // namespace pilempm_test

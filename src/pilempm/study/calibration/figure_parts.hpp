#pragma once
// Pieces of the items' figures: colours, axis labels, a curve of one test, the 2x2 figure of
// items 7 and 8 (two sets at a low and a high cell pressure), and README's image line.
#include <string>
#include <utility>
#include <vector>

#include "pilempm/study/calibration/item.hpp"
#include "pilempm/study/figures.hpp"

namespace pilempm::study::calibration {

/// matplotlib's default colour cycle: "C0" ... "C9".
std::string color(std::size_t index);

/// The curve of one test (`where` test = `test`) in an item's CSV.
SeriesSpec curve_series(const std::string& csv, const std::string& test, const std::string& x,
                        const std::string& y, const std::string& label, const std::string& colour,
                        const std::string& linestyle = "-", double linewidth = 1.6);

// Axis labels (matplotlib mathtext between $...$).
extern const std::string kAxialStrainLabel;
extern const std::string kVolumetricStrainLabel;
extern const std::string kDeviatorKPaLabel;
extern const std::string kDeviatorMPaLabel;

/// A 2x2 figure: columns low and high pressure, rows q and volumetric strain; one curve per
/// pair of tests {low, high}.
FigureSpec pressure_pair_figure(const TestResults& tests, const std::string& file,
                                const std::string& csv, const std::string& title,
                                const std::vector<std::pair<std::string, std::string>>& pairs,
                                const std::vector<std::string>& labels,
                                const std::vector<std::string>& colours,
                                const std::vector<std::string>& styles);

/// The parameter set of a test in words: "original set (φc = 31°, α = 0.12)", or the base set
/// "with stress-dependent α (0.12 → 0.01)".
std::string set_label(const TestResults& tests, const std::string& name);

/// A Markdown image line (with the blank line after it).
std::string image(const std::string& file, const std::string& alt);

}  // namespace pilempm::study::calibration

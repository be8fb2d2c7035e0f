#include "pilempm/study/calibration/readme.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "pilempm/io/output/format.hpp"

namespace pilempm::study::calibration {

namespace {

std::string anchor(std::size_t index) {
  return fmt::format("item-{}", index + 1);
}

// Markdown links to `files`, separated by commas.
std::string links(const std::vector<std::string>& files) {
  std::string out;
  for (const std::string& f : files)
    out += (out.empty() ? "" : ", ") + fmt::format("[{0}]({0})", f);
  return out;
}

}  // namespace

std::string plot_command() {
  return "/usr/bin/python3 plot_figures.py figures.json";
}

std::string study_readme(const CalibrationStudyReport& report,
                         const std::vector<std::string>& bodies) {
  std::string md = "# Calibration study: hypoplastic model, Baskarp sand\n\n";
  md += fmt::format(
      "Written by `pilempm study calibration{}` (pilempm 0.1.0). It reproduces the "
      "element-test and analytical chapters of the Deltares study (docs/study.md §2–§3: oedometer, "
      "cyclic oedometer, drained triaxial, high-pressure triaxial beside Bolton, α after Herle "
      "& Gudehus, sensitivity to α, modified against original set) and adds the "
      "stress-dependent α option (docs/study.md §5). Stresses and strains are compression "
      "positive; strains "
      "are logarithmic (sums of the increments), in percent. Each item has a CSV with the unit "
      "in every column name and a figure; the element tests behind them are in `tests/`.\n\n",
      report.quick ? " --quick" : "");
  if (report.quick)
    md +=
        "**Quick run** (`--quick`): every test ran with a quarter of the increments of "
        "`tests/case.toml`, for the test suite. The curves are coarser; run without `--quick` "
        "for the study's figures.\n\n";
  if (!report.plots.plotted)
    md += fmt::format(
        "**The figures were not drawn**: {}.{} The CSV files and `figures.json` are complete; "
        "to draw the PNG files later, in this folder (Debian: `apt-get install "
        "python3-matplotlib`):\n\n"
        "```sh\n{}\n```\n\n",
        report.plots.problem,
        report.plots.tried.empty()
            ? std::string()
            : fmt::format(" Tried: {}.", fmt::join(report.plots.tried, "; ")),
        plot_command());
  if (report.tests_failed > 0 || report.failed_items() > 0)
    md += fmt::format(
        "**{} of {} element tests failed; {} items are incomplete** (see "
        "below and `tests/summary.md`).\n\n",
        report.tests_failed, report.tests_run, report.failed_items());

  md += "## Items and their initial void-ratio convention\n\n";
  md +=
      "Every element test states how its initial void ratio e0 is meant (docs/model.md §3): "
      "`initial-stress` (e0 is the void ratio at the initial stress) or `zero-pressure` (e0 "
      "is a reference at p = 0, scaled to the initial mean stress by Bauer's law). The void "
      "ratio actually used at the start is in every table and CSV (`initial_void_ratio`).\n\n";
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < report.items.size(); ++i) {
    const StudyItem& item = report.items[i];
    std::vector<std::string> files = item.csv;
    files.insert(files.end(), item.png.begin(), item.png.end());
    rows.push_back({fmt::format("{}. [{}](#{})", i + 1, item.title, anchor(i)),
                    item.ok ? item.convention : "FAILED", links(files)});
  }
  md += markdown_table({"item", "initial void ratio convention", "files"}, rows, 3) + "\n";

  for (std::size_t i = 0; i < report.items.size(); ++i) {
    const StudyItem& item = report.items[i];
    md += fmt::format("<a id=\"{}\"></a>\n## {}. {}\n\n", anchor(i), i + 1, item.title);
    if (!item.ok) {
      md += fmt::format("**FAILED**: {}\n\n", item.error);
      continue;
    }
    md += fmt::format("*Initial void ratio*: {}.\n\n", item.convention);
    md += bodies[i];
    md += fmt::format("Data: {}.\n\n", links(item.csv));
  }

  md += "## Files\n\n";
  md += fmt::format(
      "- `README.md`: this summary; `figures.json`: every figure (file, title, axes with "
      "units, log axes, series: CSV file, columns, rows, label, style); `plot_figures.py`: "
      "the script that draws them.\n"
      "- `tests/`: the {} element tests of the study: NAME.csv (curve), NAME.json (summary: "
      "material, e0 and its convention, void ratio used, peak), `summary.md`, `summary.csv`, "
      "and `case.toml`, the case that was run (examples/study_calibration.toml); "
      "`pilempm element run tests/case.toml --out DIR` runs it again.\n\n",
      report.tests_run);
  md += "## Figures\n\n";
  if (report.plots.plotted)
    md += fmt::format("Drawn with {} and matplotlib. ", report.plots.python);
  md += fmt::format(
      "To draw them again (e.g. after editing `figures.json`), in this "
      "folder:\n\n```sh\n{}\n```\n",
      plot_command());
  return md;
}

}  // namespace pilempm::study::calibration

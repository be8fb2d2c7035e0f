#pragma once
// The description of a study's figures, written as DIR/figures.json and drawn by the generic
// plotting script tools/plot/plot_figures.py (which documents the format). A figure is a grid of
// panels; a panel has two axes (label with the unit, log or linear, optional limits) and its
// series, each a pair of columns of a CSV file, optionally restricted to the rows where some
// columns have given values (e.g. test = "oed-original-e0.70").
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pilempm {

struct AxisSpec {
  std::string label;  ///< with the unit, e.g. "vertical stress [kPa]"
  bool log = false;
  std::optional<std::pair<double, double>> limits;
  bool invert = false;  ///< values grow downwards (depth) or to the left
};

struct SeriesStyle {
  std::string color;            ///< a matplotlib colour ("C0", "#1f77b4"); "" = automatic
  std::string linestyle = "-";  ///< "-", "--", ":", "-.", or "" for markers only
  std::string marker;           ///< "" none, "o", "s", ...
  double linewidth = 1.6;       ///< [pt]
  double markersize = 0.0;      ///< [pt]; 0 = matplotlib's default
};

struct SeriesSpec {
  std::string csv;                                         ///< file name in the output folder
  std::vector<std::pair<std::string, std::string>> where;  ///< column = text filters
  std::string x, y;                                        ///< column names
  std::string label;                                       ///< legend text ("" = none)
  SeriesStyle style;
  /// A field: the points coloured by this column (with a colour bar), "" = a curve.
  std::string color_by;
  /// A field of particles: the columns of the half-lengths of each particle's domain along x
  /// and y; each particle is drawn as its filled rectangle. "" = a dot per point.
  std::string half_x, half_y;
  /// A filled polygon: the rows' (x, y) points as one polygon of this matplotlib colour with a
  /// black outline, drawn over the fields. "" = not a polygon.
  std::string fill;
  std::string color_label;                                ///< of the colour bar, with the unit
  std::string colormap = "viridis";                       ///< a matplotlib colour map
  std::optional<std::pair<double, double>> color_limits;  ///< the values at its ends
  bool color_log = false;                                 ///< a logarithmic colour scale
};

/// A curve of `y` against `x` from the rows of `csv` that match `where`.
SeriesSpec curve(std::string csv, std::vector<std::pair<std::string, std::string>> where,
                 std::string x, std::string y, std::string label, SeriesStyle style = {});

struct PanelSpec {
  std::string title;
  AxisSpec x, y;
  std::string legend = "best";  ///< a matplotlib legend location, or "none"
  std::string legend_title;
  int legend_columns = 1;
  std::vector<SeriesSpec> series;
};

struct FigureSpec {
  std::string file;   ///< PNG file name in the output folder
  std::string title;  ///< figure title
  int rows = 1, cols = 1;
  double width_in = 0.0, height_in = 0.0;  ///< size [inch]; 0 = from the layout
  bool sharex = false, sharey = false;
  bool shared_legend = false;  ///< one legend below the figure instead of one per panel
  int legend_columns = 0;      ///< of the shared legend; 0 = automatic
  std::vector<PanelSpec> panels;
};

/// figures.json: {"version": 1, "figures": [...]}, the format of tools/plot/plot_figures.py.
std::string figures_json(const std::vector<FigureSpec>& figures);

/// The CSV files the figures read, each once, in order of first use.
std::vector<std::string> figure_csv_files(const std::vector<FigureSpec>& figures);

}  // namespace pilempm

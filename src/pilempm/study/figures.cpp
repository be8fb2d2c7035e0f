#include "pilempm/study/figures.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "pilempm/core/error.hpp"
#include "pilempm/io/output/format.hpp"
#include "pilempm/io/output/json_writer.hpp"

namespace pilempm {

namespace {

// A number of a figure: a non-finite one is a mistake of the figure, not a missing value.
std::string figure_number(double value) {
  if (!std::isfinite(value)) throw Error(fmt::format("figures.json: non-finite number {}", value));
  return json_number(value);
}

std::string axis_json(const AxisSpec& axis) {
  std::string out = "{\"label\": " + json_quote(axis.label);
  if (axis.log) out += ", \"log\": true";
  if (axis.limits)
    out += fmt::format(", \"limits\": [{}, {}]", figure_number(axis.limits->first),
                       figure_number(axis.limits->second));
  if (axis.invert) out += ", \"invert\": true";
  return out + "}";
}

std::string style_json(const SeriesStyle& style) {
  std::string out =
      "{\"linestyle\": " + json_quote(style.linestyle.empty() ? "none" : style.linestyle);
  if (!style.color.empty()) out += ", \"color\": " + json_quote(style.color);
  if (!style.marker.empty()) out += ", \"marker\": " + json_quote(style.marker);
  out += ", \"linewidth\": " + figure_number(style.linewidth);
  if (style.markersize > 0.0) out += ", \"markersize\": " + figure_number(style.markersize);
  return out + "}";
}

std::string series_json(const SeriesSpec& s) {
  std::string where = "{";
  for (std::size_t i = 0; i < s.where.size(); ++i)
    where += (i ? ", " : "") + json_quote(s.where[i].first) + ": " + json_quote(s.where[i].second);
  where += "}";
  std::string color;
  if (!s.color_by.empty()) {
    color = ", \"color_by\": {\"column\": " + json_quote(s.color_by) +
            ", \"label\": " + json_quote(s.color_label) + ", \"cmap\": " + json_quote(s.colormap);
    if (s.color_limits)
      color += fmt::format(", \"limits\": [{}, {}]", figure_number(s.color_limits->first),
                           figure_number(s.color_limits->second));
    if (s.color_log) color += ", \"log\": true";
    if (!s.half_x.empty() && !s.half_y.empty())
      color += ", \"half_x\": " + json_quote(s.half_x) + ", \"half_y\": " + json_quote(s.half_y);
    color += "}";
  }
  if (!s.fill.empty()) color += ", \"fill\": " + json_quote(s.fill);
  return fmt::format(
      "{{\"csv\": {}, \"where\": {}, \"x\": {}, \"y\": {}, \"label\": {}, \"style\": {}{}}}",
      json_quote(s.csv), where, json_quote(s.x), json_quote(s.y), json_quote(s.label),
      style_json(s.style), color);
}

std::string panel_json(const PanelSpec& p) {
  std::string out = "{\"title\": " + json_quote(p.title) + ", \"legend\": " + json_quote(p.legend);
  if (!p.legend_title.empty()) out += ", \"legend_title\": " + json_quote(p.legend_title);
  if (p.legend_columns > 1) out += fmt::format(", \"legend_columns\": {}", p.legend_columns);
  out += ",\n          \"x\": " + axis_json(p.x) + ",\n          \"y\": " + axis_json(p.y);
  out += ",\n          \"series\": [";
  for (std::size_t i = 0; i < p.series.size(); ++i)
    out += (i ? ",\n            " : "\n            ") + series_json(p.series[i]);
  return out + "]}";
}

}  // namespace

SeriesSpec curve(std::string csv, std::vector<std::pair<std::string, std::string>> where,
                 std::string x, std::string y, std::string label, SeriesStyle style) {
  SeriesSpec s;
  s.csv = std::move(csv);
  s.where = std::move(where);
  s.x = std::move(x);
  s.y = std::move(y);
  s.label = std::move(label);
  s.style = std::move(style);
  return s;
}

std::string figures_json(const std::vector<FigureSpec>& figures) {
  std::string out = "{\n  \"version\": 1,\n  \"figures\": [";
  for (std::size_t f = 0; f < figures.size(); ++f) {
    const FigureSpec& fig = figures[f];
    if (fig.panels.empty() || fig.rows < 1 || fig.cols < 1 ||
        fig.panels.size() > static_cast<std::size_t>(fig.rows * fig.cols))
      throw Error(fmt::format("figure {}: {} panels do not fit a {}x{} layout", fig.file,
                              fig.panels.size(), fig.rows, fig.cols));
    out += f ? ",\n    {" : "\n    {";
    out += "\"file\": " + json_quote(fig.file) + ", \"title\": " + json_quote(fig.title);
    out += fmt::format(", \"layout\": [{}, {}]", fig.rows, fig.cols);
    if (fig.width_in > 0.0 && fig.height_in > 0.0)
      out += fmt::format(", \"size_in\": [{}, {}]", figure_number(fig.width_in),
                         figure_number(fig.height_in));
    if (fig.sharex) out += ", \"sharex\": true";
    if (fig.sharey) out += ", \"sharey\": true";
    if (fig.shared_legend) out += ", \"shared_legend\": true";
    if (fig.legend_columns > 0) out += fmt::format(", \"legend_columns\": {}", fig.legend_columns);
    out += ",\n      \"panels\": [";
    for (std::size_t p = 0; p < fig.panels.size(); ++p)
      out += (p ? ",\n        " : "\n        ") + panel_json(fig.panels[p]);
    out += "]}";
  }
  return out + "\n  ]\n}\n";
}

std::vector<std::string> figure_csv_files(const std::vector<FigureSpec>& figures) {
  std::vector<std::string> files;
  for (const FigureSpec& fig : figures)
    for (const PanelSpec& panel : fig.panels)
      for (const SeriesSpec& s : panel.series)
        if (std::find(files.begin(), files.end(), s.csv) == files.end()) files.push_back(s.csv);
  return files;
}

}  // namespace pilempm

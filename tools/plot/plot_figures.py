#!/usr/bin/env python3
"""Draws the figures described in a figures.json file as PNG files (matplotlib, Agg backend).

Written by `pilempm study calibration` next to its CSV files and run by it; run it again by hand
with

    /usr/bin/python3 plot_figures.py DIR/figures.json

(Debian: apt-get install python3-matplotlib). `--check` only tests that matplotlib can be
imported (exit status 0) and draws nothing.

figures.json (paths relative to its folder):

    {"version": 1,
     "figures": [{
        "file": "oedometer.png", "title": "...", "size_in": [11, 4.5], "dpi": 130,
        "layout": [rows, cols], "sharex": false, "sharey": false,
        "shared_legend": false,          # one legend below the figure instead of one per panel
        "panels": [{                     # row by row
           "title": "...", "legend": "best",   # a matplotlib location, or "none"
           "legend_title": "...", "legend_columns": 1,
           "x": {"label": "vertical stress [kPa]", "log": true, "limits": [lo, hi],
                 "invert": false},
           "y": {...},
           "series": [{"csv": "oedometer.csv", "where": {"test": "oed-e0.70"},
                       "x": "sigma_v_kPa", "y": "void_ratio", "label": "e0 = 0.70",
                       "style": {"color": "C0", "linestyle": "-", "marker": "",
                                 "linewidth": 1.6, "markersize": 5},
                       "color_by": {"column": "void_ratio", "label": "void ratio [-]",
                                    "cmap": "viridis", "limits": [lo, hi], "log": false,
                                    "half_x": "half_r_mm", "half_y": "half_depth_mm"},
                       "fill": "0.6"}]}]}]}

A series with "color_by" is a field coloured by that column, with a colour bar beside the panel:
with "half_x" and "half_y" (the columns of the half-lengths of each point's domain) each point is
drawn as its filled rectangle, else as a dot ("style" gives only the dot size, "markersize").
Fields with the same "limits" share their colour scale, so that panels compare.
A series with "fill" is a filled polygon of that colour through its (x, y) points, outlined with
its "style" (e.g. a pile drawn over the fields).

CSV files have one header line (comment lines starting with '#' are skipped); an empty cell or
"nan" is a gap in the curve. "where" keeps the rows whose columns equal the given texts.
Each PNG is written to FILE.tmp and renamed over FILE, so a failure never leaves half a file.
"""

import csv
import json
import math
import os
import sys

EXIT_NO_MATPLOTLIB = 3


def load_matplotlib():
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as pyplot
    except ImportError as error:
        sys.stderr.write(
            "plot_figures.py: matplotlib is not available to %s (%s); on Debian: "
            "apt-get install python3-matplotlib\n" % (sys.executable, error)
        )
        return None
    return pyplot


class Tables:
    """CSV files read once each, as lists of dicts."""

    def __init__(self, folder):
        self.folder = folder
        self.cache = {}

    def rows(self, name):
        if name not in self.cache:
            path = os.path.join(self.folder, name)
            with open(path, newline="") as handle:
                lines = (line for line in handle if not line.startswith("#"))
                self.cache[name] = list(csv.DictReader(lines))
            if not self.cache[name]:
                raise ValueError("%s has no rows" % path)
        return self.cache[name]


def number(text):
    text = (text or "").strip()
    if not text:
        return math.nan
    try:
        return float(text)
    except ValueError:
        return math.nan


def series_data(tables, series):
    rows = tables.rows(series["csv"])
    where = series.get("where", {})
    for column in list(where) + [series["x"], series["y"]]:
        if column not in rows[0]:
            raise ValueError(
                "%s has no column %r (columns: %s)"
                % (series["csv"], column, ", ".join(rows[0].keys()))
            )
    chosen = [r for r in rows if all(r[k] == str(v) for k, v in where.items())]
    if not chosen:
        raise ValueError("%s has no rows where %s" % (series["csv"], where))
    return [number(r[series["x"]]) for r in chosen], [number(r[series["y"]]) for r in chosen]


def draw_field(fig, axes, tables, series):
    """Points at (x, y) coloured by a third column, each a dot or its filled domain rectangle,
    with a colour bar."""
    spec = series["color_by"]
    x, y = series_data(tables, series)
    c, _ = series_data(tables, dict(series, x=spec["column"]))
    limits = spec.get("limits", [None, None])
    size = series.get("style", {}).get("markersize", 2.0)
    from matplotlib.colors import LogNorm, Normalize
    if spec.get("log"):
        norm = LogNorm(vmin=limits[0], vmax=limits[1])
        c = [v if v > 0 else math.nan for v in c]
    else:
        norm = Normalize(vmin=limits[0], vmax=limits[1])
    cmap = spec.get("cmap", "viridis")
    if spec.get("half_x") and spec.get("half_y"):
        from matplotlib.collections import PolyCollection
        hx, _ = series_data(tables, dict(series, x=spec["half_x"]))
        hy, _ = series_data(tables, dict(series, x=spec["half_y"]))
        cells = [[(px - a, py - b), (px + a, py - b), (px + a, py + b), (px - a, py + b)]
                 for px, py, a, b in zip(x, y, hx, hy)]
        drawn = PolyCollection(cells, array=c, cmap=cmap, norm=norm, edgecolors="face",
                               linewidths=0.0, rasterized=True)
        axes.add_collection(drawn)
        axes.update_datalim([(min(x), min(y)), (max(x), max(y))])
        axes.autoscale_view()
    else:
        drawn = axes.scatter(x, y, c=c, s=size, cmap=cmap, norm=norm, linewidths=0,
                             rasterized=True)
    axes.set_aspect("equal", adjustable="box")
    # A colour bar as tall as the panel.
    from mpl_toolkits.axes_grid1 import make_axes_locatable
    bar = make_axes_locatable(axes).append_axes("right", size="6%", pad=0.08)
    fig.colorbar(drawn, cax=bar, label=spec.get("label", ""))


def draw_polygon(axes, tables, series):
    """A filled polygon through the series' (x, y) points, over the fields."""
    x, y = series_data(tables, series)
    style = series.get("style", {})
    axes.fill(x, y, facecolor=series["fill"], edgecolor=style.get("color", "black"),
              linewidth=style.get("linewidth", 0.8), zorder=3)


def set_axis(axes, which, spec):
    if not spec:
        return
    if spec.get("log"):
        (axes.set_xscale if which == "x" else axes.set_yscale)("log")
    if "label" in spec:
        (axes.set_xlabel if which == "x" else axes.set_ylabel)(spec["label"])
    if "limits" in spec:
        (axes.set_xlim if which == "x" else axes.set_ylim)(*spec["limits"])
    if spec.get("invert"):
        (axes.invert_xaxis if which == "x" else axes.invert_yaxis)()


def draw_figure(pyplot, tables, folder, figure):
    rows, cols = figure.get("layout", [1, 1])
    panels = figure["panels"]
    if len(panels) > rows * cols:
        raise ValueError("%d panels do not fit a %dx%d layout" % (len(panels), rows, cols))
    size = figure.get("size_in", [6.4 * cols, 4.6 * rows])
    fig, axes_grid = pyplot.subplots(
        rows, cols, figsize=size, squeeze=False,
        sharex=figure.get("sharex", False), sharey=figure.get("sharey", False))
    shared = figure.get("shared_legend", False)
    legend_entries = {}
    for index, panel in enumerate(panels):
        axes = axes_grid[index // cols][index % cols]
        for series in panel["series"]:
            label = series.get("label") or "_nolegend_"
            if "color_by" in series:
                draw_field(fig, axes, tables, series)
                continue
            if "fill" in series:
                draw_polygon(axes, tables, series)
                continue
            x, y = series_data(tables, series)
            (line,) = axes.plot(x, y, label=label, **series.get("style", {}))
            if label != "_nolegend_":
                legend_entries.setdefault(label, line)
        set_axis(axes, "x", panel.get("x"))
        set_axis(axes, "y", panel.get("y"))
        if panel.get("title"):
            axes.set_title(panel["title"], fontsize="medium")
        axes.grid(True, which="major", alpha=0.35)
        if axes.get_xscale() == "log":
            axes.grid(True, which="minor", axis="x", alpha=0.12)
        location = panel.get("legend", "best")
        if not shared and location != "none" and axes.get_legend_handles_labels()[0]:
            axes.legend(loc=location, fontsize="small", title=panel.get("legend_title"),
                        ncol=panel.get("legend_columns", 1), framealpha=0.9)
    for index in range(len(panels), rows * cols):
        axes_grid[index // cols][index % cols].set_visible(False)
    if figure.get("title"):
        fig.suptitle(figure["title"], fontsize="large")
    if shared and legend_entries:
        columns = figure.get("legend_columns", min(len(legend_entries), 4))
        fig.legend(list(legend_entries.values()), list(legend_entries.keys()),
                   loc="lower center", ncol=columns, fontsize="small", frameon=False)
        legend_rows = math.ceil(len(legend_entries) / columns)
        bottom = min(0.4, (0.2 + 0.2 * legend_rows) / size[1])
        fig.tight_layout(rect=(0, bottom, 1, 1))
    else:
        fig.tight_layout()
    target = os.path.join(folder, figure["file"])
    temporary = target + ".tmp"
    try:
        fig.savefig(temporary, format="png", dpi=figure.get("dpi", 120))
        os.replace(temporary, target)
    finally:
        pyplot.close(fig)
        if os.path.exists(temporary):
            os.remove(temporary)
    return target


def main(argv):
    if len(argv) == 2 and argv[1] == "--check":
        return 0 if load_matplotlib() else EXIT_NO_MATPLOTLIB
    if len(argv) != 2:
        sys.stderr.write("usage: plot_figures.py FIGURES.json  (or --check)\n")
        return 2
    pyplot = load_matplotlib()
    if pyplot is None:
        return EXIT_NO_MATPLOTLIB
    description = argv[1]
    folder = os.path.dirname(os.path.abspath(description))
    with open(description) as handle:
        figures = json.load(handle)["figures"]
    tables = Tables(folder)
    failures = 0
    for figure in figures:
        try:
            target = draw_figure(pyplot, tables, folder, figure)
            print("plot: wrote %s" % target, flush=True)
        except (OSError, ValueError, KeyError, TypeError) as error:
            failures += 1
            sys.stderr.write("plot_figures.py: %s: %s\n" % (figure.get("file", "?"), error))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

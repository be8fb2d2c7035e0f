#!/usr/bin/env python3
"""Draws one PNG per laboratory test of a calibration: measured points against the fitted curve.

Written by `pilempm calibrate` into its output folder next to figures.json and run by it; run it
again by hand with

    /usr/bin/python3 plot_calibration.py DIR/figures.json

(Debian: apt-get install python3-matplotlib). `--check` only tests that matplotlib can be
imported (exit status 0, else 3) and draws nothing. figures.json (paths relative to its folder):

    {"tests": [{"name": "tx-100", "type": "triaxial", "x": "axial_strain_pct",
                "y": ["q_kPa", "volumetric_strain_pct"], "data": "tx-100.data.csv",
                "fit": "tx-100.fit.csv", "png": "tx-100.png"}]}

"fit" may be empty (the fitted model failed on that test): the figure then shows the data only.
Each PNG is written to FILE.tmp and renamed over FILE.
"""

import csv
import json
import os
import sys

EXIT_NO_MATPLOTLIB = 3  # the convention of plot_figures.py, which pilempm relies on

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None

LABELS = {
    "axial_strain_pct": "axial strain [%]",
    "radial_strain_pct": "radial strain [%]",
    "volumetric_strain_pct": "volumetric strain [%] (compression +)",
    "sigma_a_kPa": "axial stress [kPa]",
    "sigma_r_kPa": "radial stress [kPa]",
    "sigma_l_kPa": "lateral stress [kPa]",
    "p_kPa": "mean stress p [kPa]",
    "q_kPa": "deviator stress q [kPa]",
    "void_ratio": "void ratio [-]",
    "phi_mob_deg": "mobilised friction angle [deg]",
    "igs_rho": "intergranular strain ratio rho [-]",
}


def read_csv(path):
    with open(path, newline="") as handle:
        rows = [line for line in handle if not line.startswith("#")]
    columns = {}
    for row in csv.DictReader(rows):
        for key, value in row.items():
            number = float(value) if value not in ("", "nan") else float("nan")
            columns.setdefault(key, []).append(number)
    return columns


def draw(folder, test):
    data = read_csv(os.path.join(folder, test["data"]))
    fit = read_csv(os.path.join(folder, test["fit"])) if test.get("fit") else None
    quantities = test["y"]
    fig, axes = plt.subplots(1, len(quantities), figsize=(5.2 * len(quantities), 4.2),
                             squeeze=False)
    x = test["x"]
    for ax, y in zip(axes[0], quantities):
        ax.plot(data[x], data[y], "o", markersize=3.5, color="C0", label="measured")
        if fit is not None:
            ax.plot(fit[x], fit[y], "-", color="C3", linewidth=1.6, label="fitted")
        ax.set_xlabel(LABELS.get(x, x))
        ax.set_ylabel(LABELS.get(y, y))
        if x in ("sigma_a_kPa", "p_kPa"):
            ax.set_xscale("log")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best")
    fig.suptitle("%s (%s)" % (test["name"], test["type"]))
    fig.tight_layout()
    target = os.path.join(folder, test["png"])
    try:
        fig.savefig(target + ".tmp", dpi=120, format="png")
        os.replace(target + ".tmp", target)
    finally:
        plt.close(fig)
        if os.path.exists(target + ".tmp"):
            os.remove(target + ".tmp")
    print("plot: wrote %s" % target, flush=True)


def main(argv):
    if len(argv) != 2:
        sys.stderr.write("usage: plot_calibration.py DIR/figures.json  (or --check)\n")
        return 2
    if plt is None:
        return EXIT_NO_MATPLOTLIB
    if argv[1] == "--check":
        return 0
    folder = os.path.dirname(os.path.abspath(argv[1]))
    with open(argv[1]) as handle:
        figures = json.load(handle)
    for test in figures["tests"]:
        draw(folder, test)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

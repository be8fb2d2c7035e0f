#!/usr/bin/env python3
"""Draws the figures of the quasi-static verifications 4 and 7 (docs/verification.md §9) from the
CSV files that `bench_quasi_static footing|pile` writes: the strip footing's pressure against its
settlement, and the pile's head force against its travel with the iterations per load step.

    /usr/bin/python3 tools/plot/plot_quasi_static.py [--results results/quasi_static]
        [--figures docs/figures/verification]

The files it reads from --results, and the commands that write them:

    footing_smooth_8.csv          bench_quasi_static footing <csv> 8 0 8 3
    footing_rough_8.csv           (the same with friction 1: a rough footing)
    footing_smooth_16.csv         bench_quasi_static footing <csv> 16 0 8 3
    pile_mohr-coulomb_20.csv      bench_quasi_static pile <csv> mohr-coulomb 4 20 3
    pile_mohr-coulomb_40.csv      bench_quasi_static pile <csv> mohr-coulomb 4 40 3
    pile_hypoplastic_40.csv       QS_BBAR=1 QS_EMBEDMENT_D=2 QS_SMOOTHING=0.05 \
                                  bench_quasi_static pile <csv> hypoplastic 4 40 3
    pile_hypoplastic_80.csv       (the same with 80 steps per D)

Only python3, numpy and matplotlib. Files that are missing are left out of the figures.
"""
import argparse
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read(path):
    """The columns of a CSV file as {name: numpy array}, or None when it is missing."""
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]} if rows else None


def scatter_about_fit(x, y, degree):
    """Root-mean-square deviation of y about its least-squares polynomial in x, over mean(y)."""
    c = np.polyfit(x, y, degree)
    return math.sqrt(np.mean((y - np.polyval(c, x)) ** 2)) / abs(np.mean(y))


def two_panels():
    return plt.subplots(1, 2, figsize=(11, 4.2), dpi=100)


def finish(fig, left, right, xlabel, ylabel, title, path, drawn):
    """Labels both panels (the right one: iterations per step), saves the figure if drawn."""
    for ax in (left, right):
        ax.set_xlabel(xlabel)
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
    left.set_ylabel(ylabel)
    right.set_ylabel("Newton iterations per load step")
    fig.suptitle(title)
    fig.tight_layout()
    if drawn:
        fig.savefig(path)
    plt.close(fig)


def footing(results, figures):
    prandtl = 2.0 + math.pi
    fig, (left, right) = two_panels()
    drawn = False
    for name, label, style in [
        ("footing_smooth_8", "smooth, 8 cells under B/2", "-"),
        ("footing_rough_8", "rough, 8 cells under B/2", "--"),
        ("footing_smooth_16", "smooth, 16 cells under B/2", "-."),
    ]:
        d = read(os.path.join(results, name + ".csv"))
        if d is None:
            continue
        drawn = True
        s, q = d["settlement_over_cell"], d["pressure_over_c"]
        left.plot(np.r_[0.0, s], np.r_[0.0, q], style, marker=".", label=label)  # from rest
        right.plot(s, d["iterations"], style, marker=".", label=label)
    left.axhline(prandtl, color="k", lw=0.8)
    left.text(0.02, prandtl * 1.01, "Prandtl (2 + π) c", fontsize=8)
    left.set_ylim(0, 6.5)
    finish(fig, left, right, "settlement / cell", "q / c",
           "Rigid strip footing on Tresca soil, quasi-static (weightless, E/c = 1000)",
           os.path.join(figures, "qs_strip_footing.png"), drawn)


def pile(results, figures):
    fig, (left, right) = two_panels()
    drawn = False
    for name, label, style in [
        ("pile_mohr-coulomb_20", "Mohr-Coulomb from the surface, D/20 per step", "-"),
        ("pile_mohr-coulomb_40", "Mohr-Coulomb from the surface, D/40 per step", "--"),
        ("pile_hypoplastic_40", "hypoplastic + IGS from 2 D, D/40 per step", "-"),
        ("pile_hypoplastic_80", "hypoplastic + IGS from 2 D, D/80 per step", "--"),
    ]:
        d = read(os.path.join(results, name + ".csv"))
        if d is None:
            continue
        drawn = True
        z, f = d["depth_over_d"], d["head_force_N"]
        # The scatter about a quadratic over the last D reached (docs/verification.md §9.2).
        last = z >= z[-1] - 1.0 - 1e-9
        extra = ""
        if z[-1] >= 1.0 - 1e-9:
            extra = (f" (scatter {z[-1] - 1:.0f}-{z[-1]:.0f} D "
                     f"{100 * scatter_about_fit(z[last], f[last], 2):.1f} %)")
        left.plot(z, f, style, marker=".", ms=3, label=label + extra)
        right.plot(z, d["iterations"], style, marker=".", ms=3, label=label)
    finish(fig, left, right, "pile travel / D", "head force [N]",
           "Rigid pile (D = 20 mm, 60° cone) pushed into sand at 50 g, quasi-static, D/4 cells",
           os.path.join(figures, "qs_pile.png"), drawn)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", default="results/quasi_static")
    parser.add_argument("--figures", default="docs/figures/verification")
    args = parser.parse_args()
    os.makedirs(args.figures, exist_ok=True)
    footing(args.results, args.figures)
    pile(args.results, args.figures)


if __name__ == "__main__":
    main()

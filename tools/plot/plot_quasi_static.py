#!/usr/bin/env python3
"""Draws the figures of the quasi-static verifications 4 and 7 (docs/verification.md §9) from the
CSV files that `bench_quasi_static footing|pile` writes (scripts/quasi-static-figures.sh runs
the commands): the strip footing's pressure against its settlement, and the pile's head force against its
depth with the iterations per load step.

    /usr/bin/python3 tools/plot/plot_quasi_static.py [--results results/quasi_static]
        [--figures docs/figures/verification]

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
        ("pile_mohr-coulomb_20", "Mohr-Coulomb, D/20 per step", "-"),
        ("pile_mohr-coulomb_40", "Mohr-Coulomb, D/40 per step", "--"),
        ("pile_hypoplastic_20", "hypoplastic + IGS, D/20 per step", "-"),
        ("pile_hypoplastic_40", "hypoplastic + IGS, D/40 per step", "--"),
    ]:
        d = read(os.path.join(results, name + ".csv"))
        if d is None:
            continue
        drawn = True
        z, f = d["depth_over_d"], d["head_force_N"]
        # The scatter about a quadratic over 1-2 D (docs/verification.md §9.2), where reached.
        last = (z >= 1.0 - 1e-9) & (z <= 2.0 + 1e-9)
        extra = ""
        if z[-1] >= 2.0 - 1e-9:
            extra = f" (scatter 1-2 D {100 * scatter_about_fit(z[last], f[last], 2):.1f} %)"
        left.plot(z, f, style, marker=".", ms=3, label=label + extra)
        right.plot(z, d["iterations"], style, marker=".", ms=3, label=label)
    finish(fig, left, right, "pile tip depth / D", "head force [N]",
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

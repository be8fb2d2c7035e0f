#!/usr/bin/env python3
"""Checks and plots the MPM verification cases of issue 4 (docs/verification.md).

Reads the output folders that `pilempm mpm run examples/mpm/<name>.toml --out RESULTS/<name>`
wrote (particles_*.vtu, particles.pvd, energies.csv, bodies.csv), the case files themselves (for
the dimensions and material constants), computes the analytical or experimental reference and
the error of each verification, draws the figures into FIGURES/ and writes RESULTS/summary.md
and RESULTS/summary.csv with one row per check. Prints one line per check and exits 1 when a
check fails or a case's results are missing.

    /usr/bin/python3 tools/plot/plot_verification.py [--results results/verification]
        [--cases examples/mpm] [--figures docs/figures/verification] [--no-plots]
        [--only CASE,CASE,...]

Only python3 (3.11: tomllib), numpy and matplotlib.
"""
import argparse
import base64
import csv
import math
import os
import re
import struct
import sys
import tomllib
import xml.etree.ElementTree as ET

import numpy as np

G = 9.81  # the solver's default gravity [m/s^2]; a case's [solver] gravity_m_per_s2 wins


# ----------------------------------------------------------------------------------------------
# Reading the output


def read_vtu(path):
    """The points (n x 3) and the point fields {name: array (n,) or (n, k)} of one VTU file
    written by pilempm (binary DataArrays: base64 of [byte count][values], the count a UInt64
    or, in files of older versions, a UInt32 as the header_type says)."""
    kinds = {"Float64": "d", "Float32": "f", "Int64": "q", "Int32": "i", "UInt8": "B"}
    root = ET.parse(path).getroot()
    header = "<Q" if root.get("header_type") == "UInt64" else "<I"
    header_size = struct.calcsize(header)
    piece = root.find("UnstructuredGrid/Piece")
    fields = {}

    def decode(array):
        raw = base64.b64decode(array.text.strip())
        (count,) = struct.unpack_from(header, raw, 0)
        code = kinds[array.get("type")]
        values = np.frombuffer(raw[header_size:header_size + count], dtype="<" + code)
        k = int(array.get("NumberOfComponents", "1"))
        return values.reshape(-1, k) if k > 1 else values

    for array in piece.find("PointData"):
        fields[array.get("Name")] = decode(array)
    points = decode(piece.find("Points/DataArray"))
    return points, fields


def read_pvd(folder):
    """[(time, vtu path)] of a run's particles (part 0; part 1 holds the rigid bodies), in time
    order."""
    root = ET.parse(os.path.join(folder, "particles.pvd")).getroot()
    series = [(float(d.get("timestep")), os.path.join(folder, d.get("file")))
              for d in root.iter("DataSet") if d.get("part", "0") == "0"]
    return sorted(series)


def read_csv(path):
    """{column: np.array} of a CSV file with '#' comment lines and a header row."""
    with open(path) as f:
        rows = [line for line in f if line.strip() and not line.startswith("#")]
    reader = csv.reader(rows)
    header = next(reader)
    data = [r for r in reader]
    out = {}
    for j, name in enumerate(header):
        try:
            out[name] = np.array([float(r[j]) for r in data])
        except ValueError:
            out[name] = [r[j] for r in data]
    return out


def read_case(cases, name):
    with open(os.path.join(cases, name + ".toml"), "rb") as f:
        return tomllib.load(f)


def gravity(case):
    return case.get("solver", {}).get("gravity_m_per_s2", G)


def material(case, name):
    for m in case["material"]:
        if m["name"] == name:
            return m
    raise KeyError(name)


def cell_size(case, axis):
    a = case["grid"][axis]
    return (a["max_m"] - a["min_m"]) / a["cells"]


def particles_per_cell(region):
    n = region.get("particles_per_cell", 2)
    return (n, n) if isinstance(n, int) else tuple(n)


# ----------------------------------------------------------------------------------------------
# Bookkeeping of the checks


def status(passed):
    return "info" if passed is None else "PASS" if passed else "FAIL"


class Checks:
    def __init__(self):
        self.rows = []  # (verification, case, quantity, measured, tolerance, passed)

    def add(self, verification, case, quantity, measured, tolerance, passed):
        self.rows.append((verification, case, quantity, measured, tolerance, bool(passed)))
        status = "PASS" if passed else "FAIL"
        print(f"{status}  {verification:<18s} {case:<36s} {quantity}: {measured} "
              f"(tolerance {tolerance})", flush=True)

    def info(self, verification, case, quantity, measured):
        """A row for the table that is no check (neither passes nor fails)."""
        self.rows.append((verification, case, quantity, measured, "-", None))

    def checked(self):
        return [r for r in self.rows if r[5] is not None]

    def missing(self, verification, case, why):
        self.rows.append((verification, case, "results", "missing: " + why, "-", False))
        print(f"FAIL  {verification:<18s} {case:<36s} results missing: {why}", flush=True)

    def failed(self):
        return [r for r in self.rows if r[5] is False]

    def write(self, folder):
        with open(os.path.join(folder, "summary.csv"), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["verification", "case", "quantity", "measured", "tolerance", "status"])
            for r in self.rows:
                w.writerow(list(r[:5]) + [status(r[5])])
        with open(os.path.join(folder, "summary.md"), "w") as f:
            f.write("| verification | case | quantity | measured | tolerance | status |\n")
            f.write("|---|---|---|---|---|---|\n")
            for r in self.rows:
                f.write("| {} | `{}` | {} | {} | {} | {} |\n".format(
                    *r[:5], "**FAIL**" if r[5] is False else status(r[5])))


ONLY = None  # the case names to check (--only); None: every case file there is


def have(results, cases, name, checks, verification):
    """True when the case's results are there; a missing folder (for an existing case file) is a
    failed check."""
    if not os.path.exists(os.path.join(cases, name + ".toml")):
        return False
    if ONLY is not None and name not in ONLY:
        return False
    if not os.path.exists(os.path.join(results, name, "particles.pvd")):
        checks.missing(verification, name, os.path.join(results, name))
        return False
    return True


def new_figure(plt, *size):
    return plt.figure(figsize=size if size else (6.4, 4.2), dpi=100)


def save(fig, figures, name):
    if figures is None:
        return
    fig.tight_layout()
    fig.savefig(os.path.join(figures, name), dpi=100)


# ----------------------------------------------------------------------------------------------
# 1. Self-weight column


def column_self_weight(results, cases, figures, plt, checks):
    for geometry, label in (("plane_strain", "plane strain"), ("axisymmetric", "axisymmetric")):
        meshes, errors, sizes, profiles = [], [], [], []
        for n in (16, 32, 64):
            name = f"column_self_weight_{geometry}_{n}"
            if not have(results, cases, name, checks, "1 self-weight"):
                continue
            case = read_case(cases, name)
            region = case["region"][0]
            rho, height = region["density_kg_per_m3"], region["y_max_m"] - region["y_min_m"]
            g = gravity(case)
            series = read_pvd(os.path.join(results, name))
            points0, _ = read_vtu(series[0][1])
            points, fields = read_vtu(series[-1][1])
            y0 = points0[:, 1]
            depth = region["y_max_m"] - y0
            exact = rho * g * depth / 1e3  # kPa
            sigma_v = fields["stress_kPa_compression_positive"][:, 4]
            deep = depth >= 0.2 * height
            error = np.mean(np.abs(sigma_v[deep] - exact[deep]) / exact[deep])
            energies = read_csv(os.path.join(results, name, "energies.csv"))
            rest = energies["kinetic_J"][-1] / max(energies["internal_J"][-1], 1e-300)
            meshes.append(n)
            errors.append(error)
            sizes.append(cell_size(case, "y"))
            profiles.append((n, depth, sigma_v, rho * g * height / 1e3, height))
            checks.add("1 self-weight", name, "at rest: kinetic / internal energy",
                       f"{rest:.1e}", "< 1e-6", rest < 1e-6)
            if n == 64:
                checks.add("1 self-weight", name,
                           "mean |σ_v − ρgz| / ρgz (depth ≥ 0.2 H), finest mesh",
                           f"{100 * error:.3f} %", "< 1 %", error < 0.01)
        if len(meshes) >= 2:
            order = np.polyfit(np.log(sizes), np.log(errors), 1)[0]
            checks.add("1 self-weight", f"column_self_weight_{geometry}_*",
                       f"observed order on {len(meshes)} meshes ({', '.join(map(str, meshes))})",
                       f"{order:.2f}", "> 0.8 (first order)", order > 0.8)
        if plt is None or not meshes:
            continue
        fig = new_figure(plt, 9.6, 4.2)
        ax = fig.add_subplot(1, 2, 1)
        z = np.linspace(0, profiles[0][4], 50)
        ax.plot(profiles[0][3] * z / profiles[0][4], z, "k-", lw=1, label="ρ g z (exact)")
        for (n, depth, sigma_v, _, _), marker in zip(profiles, ("o", "s", "^")):
            ax.plot(sigma_v, depth, marker, ms=3, mfc="none", label=f"{n} cells over H")
        ax.invert_yaxis()
        ax.set_xlabel("vertical stress σ_v [kPa]")
        ax.set_ylabel("depth z = H − Y [m]")
        ax.set_title(f"Self-weight column, {label}")
        ax.legend(fontsize=8)
        ax = fig.add_subplot(1, 2, 2)
        ax.loglog(sizes, errors, "o-", label="MPM")
        if len(meshes) >= 2:
            fit = np.polyfit(np.log(sizes), np.log(errors), 1)
            hs = np.array([min(sizes), max(sizes)])
            ax.loglog(hs, np.exp(np.polyval(fit, np.log(hs))), "k--", lw=1,
                      label=f"fit: order {fit[0]:.2f}")
        ax.set_xlabel("cell size h [m]")
        ax.set_ylabel("mean relative error of σ_v (z ≥ 0.2 H)")
        ax.axhline(0.01, color="r", lw=0.8, ls=":", label="1 % tolerance")
        ax.legend(fontsize=8)
        ax.grid(True, which="both", lw=0.3)
        save(fig, figures, f"column_self_weight_{geometry}.png")
        plt.close(fig)


# ----------------------------------------------------------------------------------------------
# 2. Bar vibration


def bar_exact_displacement(t, x, v0, c, length):
    """Fixed (x = 0) - free (x = L) bar started in its first mode, v(x, 0) = v0 sin(πx / 2L):
    u(x, t) = (v0 / ω) sin(πx / 2L) sin(ωt), ω = πc / 2L."""
    omega = math.pi * c / (2.0 * length)
    return v0 / omega * math.sin(math.pi * x / (2.0 * length)) * np.sin(omega * t)


def downward_crossings(t, u):
    out = []
    for k in range(1, len(t)):
        if u[k - 1] > 0.0 >= u[k]:
            out.append(t[k - 1] + (t[k] - t[k - 1]) * u[k - 1] / (u[k - 1] - u[k]))
    return out


def bar_vibration(results, cases, figures, plt, checks):
    name = "bar_vibration"
    if not have(results, cases, name, checks, "2 bar vibration"):
        return
    case = read_case(cases, name)
    regions = case["region"]
    region = regions[0]
    m = material(case, region["material"])
    rho, young, nu = region["density_kg_per_m3"], m["young_modulus_MPa"] * 1e6, m["poisson_ratio"]
    oedometric = young * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
    c = math.sqrt(oedometric / rho)
    x_start = min(r["x_min_m"] for r in regions)
    length = max(r["x_max_m"] for r in regions) - x_start
    # The amplitude v0 of the mode from the region at the free end (velocity at its centre).
    last = max(regions, key=lambda r: r["x_max_m"])
    centre = 0.5 * (last["x_min_m"] + last["x_max_m"]) - x_start
    v0 = last["velocity_x_m_per_s"] / math.sin(math.pi * centre / (2 * length))
    period = 4 * length / c
    series = read_pvd(os.path.join(results, name))
    times = np.array([t for t, _ in series])
    points0, _ = read_vtu(series[0][1])
    tip = int(np.argmax(points0[:, 0]))
    x_tip = points0[tip, 0] - x_start
    u_tip = np.array([read_vtu(f)[1]["displacement_m"][tip, 0] for _, f in series])
    crossings = downward_crossings(times, u_tip)
    measured_period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    period_error = (measured_period - period) / period
    amplitude = np.max(np.abs(u_tip))
    exact_amplitude = float(bar_exact_displacement(length / c, x_tip, v0, c, length))
    amplitude_error = (amplitude - exact_amplitude) / exact_amplitude
    exact = bar_exact_displacement(times, x_tip, v0, c, length)
    energies = read_csv(os.path.join(results, name, "energies.csv"))
    total = energies["kinetic_J"] + energies["internal_J"] - energies["external_work_J"]
    drift = (total - total[0]) / total[0]
    periods = times[-1] / period
    checks.add("2 bar vibration", name,
               f"period (mean of {len(crossings) - 1} periods) vs 4L/c = {period * 1e3:.3f} ms",
               f"{measured_period * 1e3:.4f} ms ({100 * period_error:+.3f} %)", "±2 %",
               abs(period_error) < 0.02)
    checks.add("2 bar vibration", name,
               f"tip amplitude vs (v0/ω) sin(π x_tip/2L) = {exact_amplitude * 1e3:.4f} mm",
               f"{amplitude * 1e3:.4f} mm ({100 * amplitude_error:+.2f} %)", "±2 %",
               abs(amplitude_error) < 0.02)
    checks.add("2 bar vibration", name,
               f"max |E − E0| / E0 over {periods:.1f} periods (no damping)",
               f"{100 * np.max(np.abs(drift)):.3f} %", "< 1 %", np.max(np.abs(drift)) < 0.01)
    # The secular drift: the total averaged over the last period against the first (the staggered
    # kinetic energy makes the same-step total wobble by about ωΔt/2 within a period).
    t_e = energies["time_s"]
    first = np.mean(total[t_e <= period])
    last = np.mean(total[t_e >= t_e[-1] - period])
    secular = (last - first) / first
    checks.add("2 bar vibration", name, "period-averaged total energy, last period vs first",
               f"{100 * secular:+.3f} %", "< 1 %", abs(secular) < 0.01)
    if plt is None:
        return
    fig = new_figure(plt, 9.6, 4.2)
    ax = fig.add_subplot(1, 2, 1)
    fine = np.linspace(0, times[-1], 4000)
    ax.plot(fine / period, 1e3 * bar_exact_displacement(fine, x_tip, v0, c, length), "k-", lw=1,
            label="exact: (v0/ω) sin(πx/2L) sin(ωt)")
    ax.plot(times / period, 1e3 * u_tip, ".", ms=3, label="MPM, particle at the tip")
    ax.set_xlabel("t / (4L/c)")
    ax.set_ylabel("tip displacement [mm]")
    ax.set_title(f"Bar vibration: period {100 * period_error:+.2f} %, "
                 f"amplitude {100 * amplitude_error:+.2f} %", fontsize=10)
    ax.legend(fontsize=8, loc="lower left")
    ax = fig.add_subplot(1, 2, 2)
    t = energies["time_s"] / period
    e0 = total[0]
    ax.plot(t, energies["kinetic_J"] / e0, lw=0.8, label="kinetic")
    ax.plot(t, energies["internal_J"] / e0, lw=0.8, label="strain")
    ax.plot(t, total / e0, "k-", lw=1.2, label="total")
    ax.set_xlabel("t / (4L/c)")
    ax.set_ylabel("energy / initial energy")
    ax.set_title(f"max |total drift| {100 * np.max(np.abs(drift)):.2f} %", fontsize=10)
    ax.legend(fontsize=8, loc="center right")
    save(fig, figures, "bar_vibration.png")
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# 4. Granular column collapse


def lube_runout(a):
    """Lube, Huppert, Sparks & Freundt (2005), 2D collapses: (L∞ − L0)/L0 = 1.2 a for a < 1.8,
    1.9 a^(2/3) for a > 2.8 (interpolated between, as tests/mpm/test_column_collapse.cpp)."""
    a = np.asarray(a, dtype=float)
    low, high = 1.2 * a, 1.9 * a ** (2.0 / 3.0)
    w = np.clip((a - 1.8) / 1.0, 0.0, 1.0)
    middle = (1 - w) * 1.2 * 1.8 + w * 1.9 * 2.8 ** (2.0 / 3.0)
    return np.where(a <= 1.8, low, np.where(a >= 2.8, high, middle))


COLLAPSE_TOLERANCE = 0.25  # as in tests/mpm/test_column_collapse.cpp


def collapse_runout(results, cases, name):
    case = read_case(cases, name)
    region = case["region"][0]
    width = region["x_max_m"] - region["x_min_m"]
    aspect = (region["y_max_m"] - region["y_min_m"]) / width
    half = 0.5 * cell_size(case, "x") / particles_per_cell(region)[0]
    series = read_pvd(os.path.join(results, name))
    points, _ = read_vtu(series[-1][1])
    before, _ = read_vtu(series[-2][1])
    # The front: the right edge of the farthest particle domain (its initial half-size).
    front = np.max(points[:, 0]) + half
    creep = (front - np.max(before[:, 0]) - half) / width / (series[-1][0] - series[-2][0])
    energies = read_csv(os.path.join(results, name, "energies.csv"))
    kinetic = energies["kinetic_J"]
    return dict(aspect=aspect, width=width, runout=(front - width) / width, creep=creep,
                rest=kinetic[-1] / np.max(kinetic), points=points, half=half,
                n=round(width / cell_size(case, "x")), time=series[-1][0])


def column_collapse(results, cases, figures, plt, checks):
    runs = {}
    for name in sorted(os.listdir(cases)):
        if not name.startswith("column_collapse_") or not name.endswith(".toml"):
            continue
        name = name[:-5]
        if have(results, cases, name, checks, "4 column collapse"):
            runs[name] = collapse_runout(results, cases, name)
    by_aspect = {}
    for name, r in runs.items():
        by_aspect.setdefault(r["aspect"], []).append((r["n"], name, r))
        checks.add("4 column collapse", name,
                   f"flow over at t = {r['time']:g} s: kinetic energy / its peak "
                   f"(front still creeping at {r['creep']:.3f} L0/s)",
                   f"{r['rest']:.1e}", "< 1e-3", r["rest"] < 1e-3)
    final = {}
    for a, items in sorted(by_aspect.items()):
        items.sort()
        expected = float(lube_runout(a))
        if len(items) >= 2:  # first order in h (the rough base): Richardson from n and 2n
            (n1, _, coarse), (n2, name2, fine) = items[-2], items[-1]
            value = fine["runout"] + (fine["runout"] - coarse["runout"]) / (n2 / n1 - 1)
            label = f"runout extrapolated from {n1} and {n2} cells over L0"
            case_label = f"column_collapse a = {a:g} ({n1}, {n2})"
        else:
            n2, name2, fine = items[-1]
            value, label, case_label = fine["runout"], f"runout, {n2} cells over L0", name2
        ratio = value / expected
        final[a] = (value, [(n, r["runout"]) for n, _, r in items])
        checks.add("4 column collapse", case_label,
                   f"{label} vs Lube 2005 {expected:.3f}",
                   f"{value:.3f} (ratio {ratio:.3f})", f"±{100 * COLLAPSE_TOLERANCE:.0f} %",
                   abs(ratio - 1) < COLLAPSE_TOLERANCE)
    if plt is None or not runs:
        return
    fig = new_figure(plt, 9.6, 4.6)
    ax = fig.add_subplot(1, 2, 1)
    for k, (a, items) in enumerate(sorted(by_aspect.items())):
        n, name, r = items[-1]
        p = r["points"] / r["width"]
        # The free surface: the highest particle domain top in columns two particles wide.
        step = 4 * r["half"] / r["width"]
        bins = np.floor(p[:, 0] / step).astype(int)
        top = np.full(bins.max() + 1, np.nan)
        np.fmax.at(top, bins, p[:, 1] + step / 4)
        x = (np.arange(len(top)) + 0.5) * step
        x = np.append(x[~np.isnan(top)], x[~np.isnan(top)][-1] + step / 2)
        y = np.append(top[~np.isnan(top)], 0.0)
        ax.plot(x, y, "-", color=f"C{k}", lw=1.2,
                label=f"a = {a:g}, t = {r['time']:g} s ({n} cells/L0)")
        ax.plot([0, 1, 1], [a, a, 0], ":", color=f"C{k}", lw=0.8)
    ax.set_xlabel("x / L0")
    ax.set_ylabel("y / L0")
    ax.set_title("Final free surfaces (dotted: initial columns)", fontsize=10)
    ax.set_aspect("equal")
    ax.legend(fontsize=8)
    ax = fig.add_subplot(1, 2, 2)
    a = np.linspace(0.3, 5.0, 200)
    law = lube_runout(a)
    ax.plot(a, law, "k-", lw=1, label="Lube et al. (2005)")
    ax.fill_between(a, (1 - COLLAPSE_TOLERANCE) * law, (1 + COLLAPSE_TOLERANCE) * law,
                    color="0.85", label=f"±{100 * COLLAPSE_TOLERANCE:.0f} % (scatter)")
    first = True
    for aspect, (value, meshes) in sorted(final.items()):
        for n, runout in meshes:
            ax.plot(aspect, runout, "o", mfc="none", color="C0",
                    label="MPM, one mesh (cells over L0)" if first else None)
            ax.annotate(f"{n}", (aspect, runout), fontsize=7, xytext=(4, -2),
                        textcoords="offset points")
            first = False
    extrapolated = [(aspect, v) for aspect, (v, meshes) in final.items() if len(meshes) >= 2]
    if extrapolated:
        ax.plot(*zip(*extrapolated), "s", color="C3", label="MPM, extrapolated h → 0")
    ax.set_xlabel("aspect ratio a = H0 / L0")
    ax.set_ylabel("runout (L∞ − L0) / L0")
    ax.set_title("Runout against Lube et al. (2005)", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, lw=0.3)
    save(fig, figures, "column_collapse.png")
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# 3. Lamé thick cylinder


def lame_cylinder(results, cases, figures, plt, checks):
    runs = []
    for n in (32, 64, 128):
        name = f"lame_cylinder_{n}"
        if not have(results, cases, name, checks, "3 Lamé"):
            continue
        case = read_case(cases, name)
        region = case["region"][0]
        inner, outer = region["x_min_m"], region["x_max_m"]
        traction = [t for t in case["traction"] if t["region"] == region["name"]][0]
        pressure = traction["normal_kPa"]
        m = material(case, region["material"])
        nu = m["poisson_ratio"]
        big_a = pressure * inner ** 2 / (outer ** 2 - inner ** 2)
        big_b = big_a * outer ** 2
        h = cell_size(case, "x")
        series = read_pvd(os.path.join(results, name))
        points0, _ = read_vtu(series[0][1])
        points, fields = read_vtu(series[-1][1])
        r0, r = points0[:, 0], points[:, 0]
        stress = -fields["stress_kPa_compression_positive"]  # tension positive [kPa]
        radial, hoop, axial = stress[:, 0], stress[:, 8], stress[:, 4]
        exact_r, exact_t = big_a - big_b / r ** 2, big_a + big_b / r ** 2
        inside = (r0 > inner + 0.5 * h) & (r0 < outer - 0.5 * h)  # off the faces' layers
        e_r = np.mean(np.abs(radial[inside] - exact_r[inside])) / pressure
        e_t = np.mean(np.abs(hoop[inside] - exact_t[inside]) / np.abs(exact_t[inside]))
        e_z = np.mean(np.abs(axial[inside] - 2 * nu * big_a)) / (2 * nu * big_a)
        energies = read_csv(os.path.join(results, name, "energies.csv"))
        rest = energies["kinetic_J"][-1] / max(energies["internal_J"][-1], 1e-300)
        checks.add("3 Lamé", name, "at rest: kinetic / internal energy", f"{rest:.1e}", "< 1e-6",
                   rest < 1e-6)
        runs.append(dict(n=n, h=h, e_r=e_r, e_t=e_t, e_z=e_z, r=r, radial=radial, hoop=hoop,
                         inner=inner, outer=outer, A=big_a, B=big_b, p=pressure, name=name))
    if not runs:
        return
    finest = runs[-1]
    checks.add("3 Lamé", finest["name"], "mean |σ_r − Lamé| / p_i (off the face layers)",
               f"{100 * finest['e_r']:.3f} %", "< 2 %", finest["e_r"] < 0.02)
    checks.add("3 Lamé", finest["name"], "mean |σ_θ − Lamé| / |Lamé| (off the face layers)",
               f"{100 * finest['e_t']:.3f} %", "< 2 %", finest["e_t"] < 0.02)
    checks.add("3 Lamé", finest["name"], "mean |σ_z − 2νA| / 2νA (off the face layers)",
               f"{100 * finest['e_z']:.3f} %", "< 2 %", finest["e_z"] < 0.02)
    if len(runs) >= 2:
        hs = [x["h"] for x in runs]
        order_r = np.polyfit(np.log(hs), np.log([x["e_r"] for x in runs]), 1)[0]
        order_t = np.polyfit(np.log(hs), np.log([x["e_t"] for x in runs]), 1)[0]
        checks.add("3 Lamé", "lame_cylinder_*", f"observed order, σ_r and σ_θ, "
                   f"{', '.join(str(x['n']) for x in runs)} cells",
                   f"{order_r:.2f}, {order_t:.2f}", "> 0.6 (as the CTest test)",
                   order_r > 0.6 and order_t > 0.6)
    if plt is None:
        return
    fig = new_figure(plt, 9.6, 4.2)
    ax = fig.add_subplot(1, 2, 1)
    rr = np.linspace(finest["inner"], finest["outer"], 200)
    p = finest["p"]
    ax.plot(rr, (finest["A"] - finest["B"] / rr ** 2) / p, "k-", lw=1, label="Lamé σ_r")
    ax.plot(rr, (finest["A"] + finest["B"] / rr ** 2) / p, "k--", lw=1, label="Lamé σ_θ")
    ax.plot(finest["r"], finest["radial"] / p, "o", ms=2, mfc="none", label="MPM σ_r")
    ax.plot(finest["r"], finest["hoop"] / p, "s", ms=2, mfc="none", label="MPM σ_θ")
    ax.set_xlabel("r [m]")
    ax.set_ylabel("stress / p_i (tension positive)")
    ax.set_title(f"Lamé cylinder, {finest['n']} cells over the wall", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, lw=0.3)
    ax = fig.add_subplot(1, 2, 2)
    hs = [x["h"] for x in runs]
    ax.loglog(hs, [x["e_r"] for x in runs], "o-", label="σ_r: mean |error| / p_i")
    ax.loglog(hs, [x["e_t"] for x in runs], "s-", label="σ_θ: mean relative error")
    ax.axhline(0.02, color="r", lw=0.8, ls=":", label="2 % tolerance")
    ax.set_xlabel("cell size h [m]")
    ax.set_ylabel("error")
    ax.legend(fontsize=8)
    ax.grid(True, which="both", lw=0.3)
    save(fig, figures, "lame_cylinder.png")
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# 5. Strip footing (Prandtl)


def polygon_of(case, name):
    for b in case.get("body", []):
        if b.get("name") == name:
            return np.array(b["vertices_m"], dtype=float), b
    raise KeyError(name)


def body_rows(results, name, body):
    rows = read_csv(os.path.join(results, name, "bodies.csv"))
    keep = [i for i, b in enumerate(rows["body"]) if b == body]
    return {k: (np.asarray(v)[keep] if isinstance(v, np.ndarray) else [v[i] for i in keep])
            for k, v in rows.items()}


PRANDTL_TOLERANCE = 0.05
# A hold "stops" when the settlement over its second half is below STOP_FRACTION of the
# settlement at its end; it "runs on" when the settlement over the whole hold is more than
# RUN_ON_FACTOR times the largest one of the holds below q_u and it has not stopped by the end
# (its second half adds more than STOP_FRACTION).
STOP_FRACTION = 0.01
RUN_ON_FACTOR = 10.0


def region_named(case, name):
    for r in case["region"]:
        if r.get("name") == name:
            return r
    raise KeyError(name)


def phase_spans(case):
    """[(name, traction multiplier, start, end)] of the phases (none has a stop rule)."""
    spans, t = [], 0.0
    for i, p in enumerate(case["phase"]):
        spans.append((p.get("name", f"phase{i + 1}"), p.get("traction_multiplier", 1.0), t,
                      t + p["duration_s"]))
        t += p["duration_s"]
    return spans


def strip_load_settlement(results, case, name):
    """The load-controlled strip: (times, settlements [m], the loaded particles' count), the
    settlement being the mean downward displacement of the loaded particle row (the top row of
    the traction's region) in each VTU snapshot."""
    traction = case["traction"][0]
    region = region_named(case, traction["region"])
    h = cell_size(case, "y")
    row = h / particles_per_cell(region)[1]
    series = read_pvd(os.path.join(results, name))
    points0, _ = read_vtu(series[0][1])
    loaded = ((points0[:, 1] > region["y_max_m"] - row) & (points0[:, 0] > region["x_min_m"])
              & (points0[:, 0] < region["x_max_m"]))
    times = np.array([t for t, _ in series])
    settlement = np.array([-np.mean(read_vtu(f)[1]["displacement_m"][loaded, 1])
                           for _, f in series])
    return times, settlement, int(np.sum(loaded))


def strip_footing_load(results, cases, figures, plt, checks):
    """Verification 5: a uniform pressure on a flexible strip, stepped up to holds below and above
    Prandtl's q_u; below it the settlement must stop during a hold, above it run on."""
    curves = []
    files = [f for f in os.listdir(cases)
             if f.startswith("strip_footing_load") and f.endswith(".toml")]
    for file in sorted(files, key=lambda f: (len(f), f)):
        name = file[:-5]
        if not have(results, cases, name, checks, "5 strip footing"):
            continue
        case = read_case(cases, name)
        traction = case["traction"][0]
        region = region_named(case, traction["region"])
        cohesion = material(case, region["material"])["cohesion_kPa"]
        q_u = (2 + math.pi) * cohesion
        times, settlement, count = strip_load_settlement(results, case, name)
        eps = 1e-6

        def at(t):
            return settlement[np.argmin(np.abs(times - t))]

        holds = []  # (q/q_u, settlement at the start, middle, end of the hold)
        ratio = np.zeros_like(times)
        for phase, multiplier, start, end in phase_spans(case):
            inside = (times > start + eps) & (times <= end + eps)
            ratio[inside] = multiplier * traction["normal_kPa"] / q_u
            if phase.startswith("hold"):
                holds.append((multiplier * traction["normal_kPa"] / q_u, at(start),
                              at(0.5 * (start + end)), at(end)))
        below = [hd for hd in holds if hd[0] <= 1 - PRANDTL_TOLERANCE + eps]
        above = [hd for hd in holds if hd[0] >= 1 + PRANDTL_TOLERANCE - eps]
        if not below or not above:
            checks.missing("5 strip footing", name, "needs holds at <= 0.95 and >= 1.05 q_u")
            continue
        stopped_increment = max(hd[3] - hd[1] for hd in below)
        for level, s0, s_mid, s_end in holds:
            increment, second_half = s_end - s0, s_end - s_mid
            text = (f"settlement {1e3 * s_end:.2f} mm, +{1e3 * increment:.2f} mm over the hold, "
                    f"+{1e3 * second_half:.3f} mm ({100 * second_half / s_end:.2f} %) over its "
                    f"second half")
            if level <= 1 - PRANDTL_TOLERANCE + eps:
                checks.add("5 strip footing", name, f"hold at q = {level:.2f} q_u stops: {text}",
                           f"{100 * second_half / s_end:.2f} %",
                           f"second half < {100 * STOP_FRACTION:g} % of the settlement",
                           second_half < STOP_FRACTION * s_end)
            elif level >= 1 + PRANDTL_TOLERANCE - eps:
                factor = increment / stopped_increment if stopped_increment > 0 else math.inf
                checks.add("5 strip footing", name,
                           f"hold at q = {level:.2f} q_u runs on: {text}; the hold adds "
                           f"{factor:.1f} x the most a hold below q_u adds",
                           f"{factor:.1f} x, second half {100 * second_half / s_end:.1f} %",
                           f"> {RUN_ON_FACTOR:g} x and > {100 * STOP_FRACTION:g} %",
                           factor > RUN_ON_FACTOR and second_half > STOP_FRACTION * s_end)
            else:
                print(f"INFO  5 strip footing     {name:<36s} hold at q = {level:.2f} q_u: "
                      f"settlement {text}", flush=True)
        # The bracket: the highest hold that stops and the lowest that runs on.
        stops = [hd[0] for hd in holds if hd[3] - hd[2] < STOP_FRACTION * hd[3]]
        runs = [hd[0] for hd in holds if hd[3] - hd[2] > STOP_FRACTION * hd[3]
                and hd[3] - hd[1] > RUN_ON_FACTOR * stopped_increment]
        low, high = (max(stops) if stops else 0.0), (min(runs) if runs else math.inf)
        checks.add("5 strip footing", name,
                   "collapse load between the highest hold that stops and the lowest that runs "
                   "on, vs Prandtl's (2 + π) c", f"{low:.2f} q_u < q_collapse <= {high:.2f} q_u",
                   f"within ±{100 * PRANDTL_TOLERANCE:.0f} %",
                   low >= 1 - PRANDTL_TOLERANCE - eps and high <= 1 + PRANDTL_TOLERANCE + eps
                   and low < high and not any(low < r < high or r < low for r in runs))
        curves.append((name, case, times, settlement, ratio, holds, count))
    return curves


def strip_footing_rigid(results, cases, checks):
    """The rigid footing pushed into the soil (a [[body]] polygon): informational only. Its
    nodal contact takes in the next row of nodes every h/2 of settlement and the load jumps by
    about 20 % then, before the soil reaches its plateau on fine meshes."""
    curves = []
    files = [f for f in os.listdir(cases) if re.fullmatch(r"strip_footing_\d+\.toml", f)]
    for file in sorted(files, key=lambda f: (len(f), f)):
        name = file[:-5]
        if not os.path.exists(os.path.join(cases, name + ".toml")):
            continue
        if ONLY is not None and name not in ONLY:
            continue
        if not os.path.exists(os.path.join(results, name, "bodies.csv")):
            print(f"INFO  5 strip footing     {name:<36s} (rigid footing) no results", flush=True)
            continue
        case = read_case(cases, name)
        vertices, _ = polygon_of(case, "footing")
        half_width = np.max(vertices[:, 0])  # the footing from the symmetry plane x = 0
        region = case["region"][0]
        cohesion = material(case, region["material"])["cohesion_kPa"]
        rows = body_rows(results, name, "footing")
        settlement = -rows["displacement_y_m"]
        q = rows["force_y_N"] / half_width / 1e3  # kPa
        h = cell_size(case, "x")
        plateau = (settlement >= 0.2 * h - 1e-9) & (settlement <= 0.5 * h + 1e-9)
        limit = np.mean(q[plateau]) / cohesion
        error = limit / (2 + math.pi) - 1
        print(f"INFO  5 strip footing     {name:<36s} rigid footing (not a check): mean q/c over "
              f"the settlements 0.2 h to 0.5 h = {limit:.3f} ({100 * error:+.2f} % of 2 + π)",
              flush=True)
        checks.info("5 strip footing", name,
                    "rigid footing, mean q/c over the settlements 0.2 h to 0.5 h vs 2 + π "
                    "(informational: limited by the nodal contact)",
                    f"{limit:.3f} ({100 * error:+.2f} %)")
        curves.append((name, 2 * half_width, settlement, q / cohesion,
                       round(half_width / h)))
    return curves


def strip_footing(results, cases, figures, plt, checks):
    load_curves = strip_footing_load(results, cases, figures, plt, checks)
    rigid_curves = strip_footing_rigid(results, cases, checks)
    if plt is None or not (load_curves or rigid_curves):
        return
    fig = new_figure(plt, 11.0, 4.4)
    ax = fig.add_subplot(1, 2, 1)
    below_labels = 0
    for i, (name, case, times, settlement, ratio, holds, count) in enumerate(load_curves):
        h = cell_size(case, "x")
        n = round(region_named(case, case["traction"][0]["region"])["x_max_m"] / h)
        line, = ax.plot(1e3 * settlement[1:], ratio[1:], ".-", lw=0.8, ms=3,
                        label=f"MPM, {n} cells under B/2 ({name})")
        for level, s0, s_mid, s_end in holds:
            ax.plot([1e3 * s0, 1e3 * s_end], [level, level], "-", lw=2.5,
                    color=line.get_color(), alpha=0.5)
            label = f"+{1e3 * (s_end - s0):.2f} mm (+{1e3 * (s_end - s_mid):.2f})"
            if level < 1:  # the holds below q_u, short, listed in the free upper left
                ax.text(0.12, 1.27 - 0.045 * below_labels, f"hold at {level:.2f} q_u: {label}",
                        fontsize=6.5, va="top", color=line.get_color())
                below_labels += 1
            else:  # above the hold's line (below it for the second mesh)
                ax.annotate(label, (1e3 * s0, level), xytext=(2, 3 if i == 0 else -3),
                            textcoords="offset points", fontsize=6.5, ha="left",
                            va="bottom" if i == 0 else "top", color=line.get_color())
    ax.axhline(1.0, color="k", lw=1, label="Prandtl: q_u = (2 + π) c")
    ax.axhspan(1 - PRANDTL_TOLERANCE, 1 + PRANDTL_TOLERANCE, color="0.85", label="±5 %")
    ax.set_xscale("log")
    ax.set_xlim(0.1, 300)
    ax.set_xlabel("settlement of the loaded strip [mm] (log scale)")
    ax.set_ylabel("q / q_u")
    ax.set_title("Flexible strip, uniform pressure q (load-controlled);\n"
                 "labels: settlement over each hold (over its second half)", fontsize=9)
    ax.set_ylim(0, 1.3)
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(True, lw=0.3)
    ax = fig.add_subplot(1, 2, 2)
    for name, width, s, qc, n in rigid_curves:
        ax.plot(s / width, qc, "-", lw=1, label=f"MPM, {n} cells under B/2 ({name})")
    ax.axhline(2 + math.pi, color="k", lw=1, label="Prandtl: 2 + π")
    ax.axhspan((2 + math.pi) * (1 - PRANDTL_TOLERANCE), (2 + math.pi) * (1 + PRANDTL_TOLERANCE),
               color="0.85", label="±5 %")
    ax.set_xlabel("settlement / B")
    ax.set_ylabel("bearing pressure q / c")
    ax.set_title("For comparison (not a check): rigid footing pushed in;\n"
                 "the nodal contact steps every h/2 of settlement", fontsize=9)
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(True, lw=0.3)
    save(fig, figures, "strip_footing.png")
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# 6. Block on an inclined plane


def inclined_plane(results, cases, figures, plt, checks):
    curves = []
    for name in ("inclined_plane_slide", "inclined_plane_stick"):
        if not have(results, cases, name, checks, "6 inclined plane"):
            continue
        case = read_case(cases, name)
        vertices, body = polygon_of(case, "plane")
        top = vertices[vertices[:, 1] > np.min(vertices[:, 1]) + 1e-12]
        theta = math.atan(abs((top[1, 1] - top[0, 1]) / (top[1, 0] - top[0, 0])))
        mu = math.tan(math.radians(body["interface_friction_angle_deg"]))
        g = gravity(case)
        series = read_pvd(os.path.join(results, name))
        # Every particle has the same mass (equal sub-cells, plane strain): the centre of mass
        # moves with the mean velocity. Downslope: the plane falls to the right.
        down = np.array([math.cos(theta), -math.sin(theta)])
        t = np.array([s[0] for s in series])
        v = np.array([np.mean(read_vtu(f)[1]["velocity_m_per_s"][:, :2], axis=0) @ down
                      for _, f in series])
        expected = g * (math.sin(theta) - mu * math.cos(theta))
        fit = t >= 0.05  # after the block has settled on the plane (as the CTest test)
        if expected > 0:
            slope = np.polyfit(t[fit], v[fit], 1)[0]
            error = slope / expected - 1
            checks.add("6 inclined plane", name,
                       f"θ = {math.degrees(theta):.0f}°, μ = {mu:.2f}: acceleration (fit t ≥ 0.05 s) "
                       f"vs g(sin θ − μ cos θ) = {expected:.4f} m/s²",
                       f"{slope:.4f} m/s² ({100 * error:+.2f} %)", "±2 %", abs(error) < 0.02)
        else:
            free = g * math.sin(theta) * t[-1]
            largest = np.max(np.abs(v[fit]))
            checks.add("6 inclined plane", name,
                       f"θ = {math.degrees(theta):.0f}°, μ = {mu:.2f} (sticks): largest |v| for "
                       f"t ≥ 0.05 s vs free sliding g sin θ t = {free:.3f} m/s",
                       f"{largest:.2e} m/s ({100 * largest / free:.2f} %)", "< 1 %",
                       largest < 0.01 * free)
        curves.append((name, theta, mu, t, v, max(expected, 0.0)))
    if plt is None or not curves:
        return
    fig = new_figure(plt)
    ax = fig.add_subplot(1, 1, 1)
    for k, (name, theta, mu, t, v, expected) in enumerate(curves):
        label = f"θ = {math.degrees(theta):.0f}°, μ = {mu:.2f}"
        ax.plot(t, v, "o", ms=3, color=f"C{k}", label=f"MPM, {label}")
        ax.plot(t, expected * t, "-", lw=1, color=f"C{k}",
                label=f"max(0, g(sin θ − μ cos θ)) t, {label}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("block velocity down the slope [m/s]")
    ax.set_title("Block on an inclined plane with Coulomb friction", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, lw=0.3)
    save(fig, figures, "inclined_plane.png")
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# 7. Restart


def restart(results, cases, figures, plt, checks):
    name = "restart_collapse"
    if not have(results, cases, name, checks, "7 restart"):
        return
    resumed = name + "_resumed"
    if not os.path.exists(os.path.join(results, resumed, "particles.pvd")):
        checks.missing("7 restart", resumed, os.path.join(results, resumed))
        return
    through = read_csv(os.path.join(results, name, "energies.csv"))
    again = read_csv(os.path.join(results, resumed, "energies.csv"))
    columns = [c for c in through if c.endswith("_J")]
    same_rows = len(through["time_s"]) == len(again["time_s"])
    energy_diff = max(np.max(np.abs(through[c] - again[c])) /
                      max(np.max(np.abs(through[c])), 1e-300) for c in columns) \
        if same_rows else float("inf")
    a_points, a_fields = read_vtu(read_pvd(os.path.join(results, name))[-1][1])
    b_points, b_fields = read_vtu(read_pvd(os.path.join(results, resumed))[-1][1])
    position_diff = np.max(np.abs(a_points - b_points))
    stress_diff = np.max(np.abs(a_fields["stress_kPa_compression_positive"] -
                                b_fields["stress_kPa_compression_positive"]))
    checks.add("7 restart", resumed, "energies.csv against the run that went through: largest "
               "relative difference", f"{energy_diff:.1e} ({len(again['time_s'])} rows)",
               "< 1e-12", energy_diff < 1e-12)
    checks.add("7 restart", resumed, "final particles: largest |Δx| [m], |Δσ| [kPa]",
               f"{position_diff:.1e}, {stress_diff:.1e}", "< 1e-12", 
               position_diff < 1e-12 and stress_diff < 1e-9)
    if plt is None:
        return
    fig = new_figure(plt, 9.6, 4.2)
    ax = fig.add_subplot(1, 2, 1)
    ax.plot(through["time_s"], through["kinetic_J"], "-", lw=2, color="0.6",
            label="uninterrupted run")
    ax.plot(again["time_s"], again["kinetic_J"], "--", lw=1, color="C3",
            label="restarted from the checkpoint")
    case = read_case(cases, name)
    t_restart = case["phase"][0]["duration_s"]
    ax.axvline(t_restart, color="k", lw=0.6, ls=":", label="checkpoint (end of phase 1)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("kinetic energy [J/m]")
    ax.legend(fontsize=8)
    ax.set_title("Restart: column collapse a = 2", fontsize=10)
    ax = fig.add_subplot(1, 2, 2)
    ax.scatter(a_points[:, 0], a_points[:, 1], s=6, color="0.6", label="uninterrupted")
    ax.scatter(b_points[:, 0], b_points[:, 1], s=1, color="C3", label="restarted")
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"final particles: max |Δx| = {position_diff:.1e} m", fontsize=10)
    ax.legend(fontsize=8, markerscale=3)
    save(fig, figures, "restart.png")
    plt.close(fig)


# ----------------------------------------------------------------------------------------------


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--results", default="results/verification")
    parser.add_argument("--cases", default="examples/mpm")
    parser.add_argument("--figures", default="docs/figures/verification")
    parser.add_argument("--no-plots", action="store_true")
    parser.add_argument("--only", help="comma-separated case names to check (default: all the "
                        "verification case files in --cases)")
    args = parser.parse_args()
    global ONLY
    if args.only:
        ONLY = set(args.only.split(","))
    plt = None
    if not args.no_plots:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        os.makedirs(args.figures, exist_ok=True)
    figures = None if args.no_plots else args.figures
    os.makedirs(args.results, exist_ok=True)
    checks = Checks()
    for verification in (column_self_weight, bar_vibration, lame_cylinder, column_collapse,
                         strip_footing, inclined_plane, restart):
        try:
            verification(args.results, args.cases, figures, plt, checks)
        except Exception as e:  # a broken case must not hide the others
            checks.missing(verification.__name__, "-", f"{type(e).__name__}: {e}")
    checks.write(args.results)
    failed = checks.failed()
    print(f"{len(checks.checked()) - len(failed)} of {len(checks.checked())} checks passed; "
          f"table in {os.path.join(args.results, 'summary.md')}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Plots of a gap diagnosis (softwrist diagnose): every trial's measurements beside the nominal and the corrected
model, and the residual map over angle and pressure. Reads OUT/curves.csv and OUT/residual_map.csv, writes PNGs
into OUT and OUT/plots.json (file, caption and each panel's axis labels, in page order, as plot_run.py does).
Usage: plot_diagnosis.py OUT"""
import csv
import json
import os
import sys
from collections import defaultdict

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_run import save  # noqa: E402  (one type size and one rule for both scripts' plots.json)

MUSCLES = ["flexor", "extensor", "ulnar", "radial"]
X_AXES = {"torque_sweep": ("angle_deg", "wrist angle [deg] (flexion +)"),
          "tensile": ("contraction", "contraction ratio [-]")}


CHANNELS = ["flexion/extension", "ulnar/radial", "flexor pressure", "extensor pressure", "ulnar pressure",
            "radial pressure"]


def number(text):
    return float(text) if text != "" else float("nan")


def trajectory_panels(axes, rows, unit):
    """One panel per channel (two angles, or four measured pressures) against time."""
    channels = sorted({int(r["channel"]) for r in rows})
    for channel, ax in zip(channels, axes):
        sel = [r for r in rows if r["channel"] == str(channel)]
        t = [number(r["t_s"]) for r in sel]
        ax.plot(t, [number(r["measured"]) for r in sel], ".", ms=1.5, color="0.45", label="real")
        ax.plot(t, [number(r["nominal"]) for r in sel], "--", color="C0", label="nominal model")
        ax.plot(t, [number(r["corrected"]) for r in sel], "-", color="C1", label="corrected model")
        ax.set_xlabel("time [s]")
        ax.set_ylabel(CHANNELS[channel] + f" [{unit}]")
        ax.grid(alpha=0.3)


def range_of_motion_panel(ax, rows, unit):
    """By muscle, its repetitions side by side: the settled angle measured, and the two models'."""
    by_muscle = defaultdict(list)
    for r in rows:
        by_muscle[r.get("muscle", "")].append(r)
    names = [m for m in MUSCLES if m in by_muscle] + sorted(m for m in by_muscle if m not in MUSCLES)
    for index, muscle in enumerate(names):
        sel = by_muscle[muscle]
        xs = [index + (k - (len(sel) - 1) / 2) * 0.12 for k in range(len(sel))]
        ax.plot(xs, [number(r["measured"]) for r in sel], "o", ms=5, color="0.3",
                label="real (each repetition)" if index == 0 else None)
        ax.plot(xs, [number(r["nominal"]) for r in sel], "_", ms=16, mew=2, color="C0",
                label="nominal model" if index == 0 else None)
        ax.plot(xs, [number(r["corrected"]) for r in sel], "_", ms=16, mew=2, color="C1",
                label="corrected model" if index == 0 else None)
    ax.set_xticks(range(len(names)), [f"{m or '?'}\n({len(by_muscle[m])} repetitions)" for m in names])
    ax.set_xlim(-0.6, len(names) - 0.4)
    ax.set_xlabel("muscle at its pressure")
    ax.set_ylabel(f"settled angle, own direction [{unit}]")
    ax.grid(axis="y", alpha=0.3)


def curve_panel(ax, rows, kind, unit):
    """Sweeps by pressure, tensile tests by pressure and direction: measured points, the models as lines."""
    x_key, x_label = X_AXES[kind]
    groups = defaultdict(list)
    for r in rows:
        key = f"{number(r['pressure_kpa']):g} kPa"
        if kind == "tensile":
            key += ", loading" if r["motion"] == "1" else ", unloading"
        groups[key].append(r)
    for key, sel in sorted(groups.items(), key=lambda kv: number(kv[0].split()[0])):
        sel = sorted(sel, key=lambda r: number(r[x_key]))
        xs = [number(r[x_key]) for r in sel]
        line, = ax.plot(xs, [number(r["measured"]) for r in sel], "o", ms=3.5, label=f"real, {key}")
        ax.plot(xs, [number(r["nominal"]) for r in sel], "--", color=line.get_color())
        ax.plot(xs, [number(r["corrected"]) for r in sel], "-", color=line.get_color())
    ax.set_xlabel(x_label)
    ax.set_ylabel(("torque" if kind == "torque_sweep" else "force") + f" [{unit}]")
    ax.grid(alpha=0.3)


def main(out):
    trials = defaultdict(list)
    with open(os.path.join(out, "curves.csv")) as f:
        for row in csv.DictReader(f):
            trials[(row["experiment"], row["kind"], row["unit"])].append(row)
    plots = []
    for index, ((name, kind, unit), rows) in enumerate(trials.items()):
        if kind == "trajectory":
            channels = len({r["channel"] for r in rows})
            fig, axes = plt.subplots(channels, 1, figsize=(10, 2.6 * channels), squeeze=False)
            trajectory_panels([a[0] for a in axes], rows, unit)
            axes[0][0].legend(loc="upper right", ncol=3, markerscale=4)
            what = "against time"
        else:
            fig, ax = plt.subplots(figsize=(8, 4.5))
            if kind == "range_of_motion":
                range_of_motion_panel(ax, rows, unit)
                what = "by muscle, each repetition"
            else:
                curve_panel(ax, rows, kind, unit)
                what = "by pressure; points measured, dashed lines the nominal model, solid the corrected"
            ax.legend(loc="best")
        save(fig, out, f"trial_{index:02d}.png", f"{name} ({kind.replace('_', ' ')}): real data beside the nominal "
             f"and the corrected model, {what}.", plots, dpi=100)

    cells = defaultdict(list)
    with open(os.path.join(out, "residual_map.csv")) as f:
        for row in csv.DictReader(f):
            cells[row["experiment"]].append(row)
    for index, (name, rows) in enumerate(cells.items()):
        fig, ax = plt.subplots(figsize=(7, 4.5))
        angles = [number(r["angle_deg"]) for r in rows]
        pressures = [number(r["pressure_kpa"]) for r in rows]
        ratio = [number(r["residual"]) / number(r["noise"]) if number(r["noise"]) > 0 else 0.0 for r in rows]
        sc = ax.scatter(angles, pressures, c=ratio, s=160, marker="s", cmap="viridis")
        significant = [(a, p) for a, p, r in zip(angles, pressures, rows) if r["significant"] == "1"]
        if significant:
            ax.plot(*zip(*significant), "rx", ms=7, mew=2, linestyle="none", label="significant")
            ax.legend(loc="best")
        fig.colorbar(sc, label="systematic residual / noise [-]")
        ax.set_xlabel("wrist angle [deg] (flexion +)")
        ax.set_ylabel("pressure [kPa]")
        save(fig, out, f"residual_map_{index:02d}.png", f"Where the nominal model misses in {name}: the systematic "
             "residual over angle and pressure, in units of what noise alone would give (x: significant).", plots,
             dpi=100)
    with open(os.path.join(out, "plots.json"), "w") as f:
        json.dump(plots, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[1])

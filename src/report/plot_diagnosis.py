#!/usr/bin/env python3
"""Plots of a gap diagnosis (softwrist diagnose): every trial's measurements beside the nominal and the corrected
model, and the residual map over angle and pressure. Reads OUT/curves.csv and OUT/residual_map.csv, writes PNGs
into OUT. Usage: plot_diagnosis.py OUT"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


CHANNELS = ["flexion/extension", "ulnar/radial", "flexor pressure", "extensor pressure", "ulnar pressure",
            "radial pressure"]


def number(text):
    return float(text) if text != "" else float("nan")


def main(out):
    trials = defaultdict(list)
    with open(os.path.join(out, "curves.csv")) as f:
        for row in csv.DictReader(f):
            trials[(row["experiment"], row["kind"], row["unit"])].append(row)
    for index, ((name, kind, unit), rows) in enumerate(trials.items()):
        # Trajectories: one panel per channel (two angles, or four measured pressures).
        channels = sorted({int(r["channel"]) for r in rows}) if kind == "trajectory" else [None]
        fig, axes = plt.subplots(1, len(channels), figsize=(5 * len(channels) if kind == "trajectory" else 6, 4),
                                 squeeze=False)
        if kind == "trajectory":
            for channel, ax in zip(channels, axes[0]):
                sel = [r for r in rows if r["channel"] == str(channel)]
                t = [number(r["t_s"]) for r in sel]
                ax.plot(t, [number(r["measured"]) for r in sel], ".", ms=1, color="0.5", label="real")
                ax.plot(t, [number(r["nominal"]) for r in sel], "--", label="nominal")
                ax.plot(t, [number(r["corrected"]) for r in sel], "-", label="corrected")
                ax.set_xlabel("t [s]")
                ax.set_ylabel(CHANNELS[channel] + f" [{unit}]")
        else:
            ax = axes[0][0]
            x_key = {"torque_sweep": "angle_deg", "tensile": "contraction", "range_of_motion": "pressure_kpa"}[kind]
            groups = defaultdict(list)
            for r in rows:
                key = r["pressure_kpa"] if kind != "range_of_motion" else r["angle_deg"][:0]
                if kind == "tensile":
                    key += " kPa " + ("loading" if r["motion"] == "1" else "unloading")
                groups[key].append(r)
            for key, sel in sorted(groups.items(), key=lambda kv: number(kv[0].split()[0]) if kv[0] else 0):
                if kind == "range_of_motion":
                    xs = list(range(len(sel)))
                else:
                    sel = sorted(sel, key=lambda r: number(r[x_key]))
                    xs = [number(r[x_key]) for r in sel]
                line, = ax.plot(xs, [number(r["measured"]) for r in sel], "o", ms=3, label=f"real {key}")
                ax.plot(xs, [number(r["nominal"]) for r in sel], "--", color=line.get_color())
                ax.plot(xs, [number(r["corrected"]) for r in sel], "-", color=line.get_color())
            ax.set_xlabel("measurement" if kind == "range_of_motion" else x_key)
            ax.set_ylabel(f"measured [{unit}]")
        axes[0][0].set_title(f"{name}: real (dots), nominal (dashed), corrected (solid)", fontsize=9)
        axes[0][0].legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(os.path.join(out, f"trial_{index:02d}.png"), dpi=90)
        plt.close(fig)

    cells = defaultdict(list)
    with open(os.path.join(out, "residual_map.csv")) as f:
        for row in csv.DictReader(f):
            cells[row["experiment"]].append(row)
    for index, (name, rows) in enumerate(cells.items()):
        fig, ax = plt.subplots(figsize=(6, 4))
        angles = [number(r["angle_deg"]) for r in rows]
        pressures = [number(r["pressure_kpa"]) for r in rows]
        ratio = [number(r["residual"]) / number(r["noise"]) if number(r["noise"]) > 0 else 0.0 for r in rows]
        sc = ax.scatter(angles, pressures, c=ratio, s=140, marker="s", cmap="viridis")
        for a, p, r in zip(angles, pressures, rows):
            if r["significant"] == "1":
                ax.plot(a, p, "rx", ms=6)
        fig.colorbar(sc, label="systematic residual / noise")
        ax.set_xlabel("angle [deg]")
        ax.set_ylabel("pressure [kPa]")
        ax.set_title(f"residual map: {name} (x: significant)", fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(out, f"residual_map_{index:02d}.png"), dpi=90)
        plt.close(fig)


if __name__ == "__main__":
    main(sys.argv[1])

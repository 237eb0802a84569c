#!/usr/bin/env python3
"""Plots of one softwrist run directory, for `softwrist report` (matplotlib, Agg backend: no display).

usage: plot_run.py RUN_DIR OUT_DIR
Writes PNGs into OUT_DIR and OUT_DIR/plots.json: [{"file", "caption", "axes": [{"xlabel", "ylabel"}]}], in page
order; "axes" lists each panel's axis labels (the report's browser test checks every panel names both, with units).
The run's kind (trials.json) chooses the plots; every number comes from the run's own files.
"""
import csv
import json
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Type a reader can read at the page's width: figures are shown at most 1056 px wide.
plt.rcParams.update({"font.size": 10, "axes.titlesize": 10, "legend.fontsize": 9, "xtick.labelsize": 9,
                     "ytick.labelsize": 9})


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if line.strip() and not line.startswith("#")))


def axes_labels(fig):
    """Each panel's axis labels; a panel sharing an axis with a labelled one takes that one's label."""
    def label(ax, axis):
        own = ax.get_xlabel() if axis == "x" else ax.get_ylabel()
        if own:
            return own
        group = ax.get_shared_x_axes() if axis == "x" else ax.get_shared_y_axes()
        shared = [other.get_xlabel() if axis == "x" else other.get_ylabel() for other in group.get_siblings(ax)]
        return next((text for text in shared if text), "")

    return [{"xlabel": label(ax, "x"), "ylabel": label(ax, "y"), "x_categorical": categorical_x(ax)}
            for ax in fig.axes if ax.get_label() != "<colorbar>" and ax.get_visible()]


def categorical_x(ax):
    """Whether the x axis names categories (muscles, directions) rather than a quantity with a unit."""
    def number(text):
        try:
            float(text.replace("\u2212", "-"))
            return True
        except ValueError:
            return False
    texts = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
    return bool(texts) and not all(number(t) for t in texts)


def save(fig, out_dir, name, caption, plots, dpi=110):
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, name), dpi=dpi)  # draws the figure: its tick labels are known from here
    plots.append({"file": name, "caption": caption, "axes": axes_labels(fig)})
    plt.close(fig)


def torque_validation(run, summary, out, plots):
    """One panel per pressure (what a reader compares: the measurement and the three models at that pressure)."""
    curves = read_csv(os.path.join(run, "model_curves.csv"))
    methods = [("fixed_no_stretch_nm", "no stretching", ":"), ("fixed_stretch_nm", "one-shot stretching", "--"),
               ("fixed_stretch_selfconsistent_nm", "self-consistent stretching", "-")]
    by_pressure = defaultdict(list)
    for row in curves:
        by_pressure[float(row["pressure_kpa"])].append(row)
    pressures = sorted(by_pressure)
    columns = min(3, len(pressures))
    rows_of_panels = (len(pressures) + columns - 1) // columns
    fig, axes = plt.subplots(rows_of_panels, columns, figsize=(11, 3.4 * rows_of_panels), sharey=True,
                             squeeze=False)
    for index, pressure in enumerate(pressures):
        ax = axes[index // columns][index % columns]
        rows = by_pressure[pressure]
        angles = [float(r["angle_deg"]) for r in rows]
        for column, label, style in methods:
            ax.plot(angles, [float(r[column]) for r in rows], style, color="C0", linewidth=1.2, label=label)
        groups = [g for g in summary["groups"] if g["pressure_kpa"] == pressure]
        ax.errorbar([g["angle_deg"] for g in groups], [g["torque_nm"] for g in groups],
                    yerr=[g["torque_std_nm"] for g in groups], fmt="o", color="k", markersize=4,
                    label="measured (mean ± SD)")
        ax.set_title(f"{pressure:g} kPa")
        ax.set_xlabel("wrist angle [deg] (flexion +)")
        if index % columns == 0:
            ax.set_ylabel("flexor torque [N m]")
        ax.grid(alpha=0.3)
    for index in range(len(pressures), rows_of_panels * columns):
        axes[index // columns][index % columns].set_visible(False)
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower right", bbox_to_anchor=(0.97, 0.1) if len(pressures) % columns else None)
    save(fig, out, "torque_angle.png",
         "Flexor torque against wrist angle at each pressure (Fig. ExperimentalData): the simulated measurement (mean "
         "and spread of the repetitions) and the analytic model with three treatments of the mounts' stretching.",
         plots)


def range_of_motion(run, summary, out, plots):
    muscles = summary["muscles"]
    labels = [m["direction"] for m in muscles]
    series = [("settled_deg", "simulated"), ("analytic_settled_deg", "analytic statics"),
              ("analytic_limit_deg", "modeled limit (torque 0)"), ("paper_exosuit_deg", "paper, exosuit"),
              ("paper_biological_deg", "paper, biological")]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    width = 0.8 / len(series)
    for i, (key, label) in enumerate(series):
        values = [m[key] if m[key] is not None else 0.0 for m in muscles]
        errors = [m["settled_std_deg"] for m in muscles] if key == "settled_deg" else None
        ax.bar([j + i * width for j in range(len(muscles))], values, width, yerr=errors, label=label)
    ax.set_xticks([j + 0.4 - width / 2 for j in range(len(muscles))], labels)
    ax.set_xlabel("direction the muscle moves the wrist")
    ax.set_ylabel("range of motion [deg]")
    ax.grid(axis="y", alpha=0.3)
    ax.legend()
    save(fig, out, "range_of_motion.png",
         "Range of motion per direction (Table RoM): simulated settled angle, analytic statics, the modeled limit, "
         "and the paper's measured exosuit and biological ranges.", plots)


def design_optimization(run, summary, out, plots):
    rows = read_csv(os.path.join(run, "design_curve.csv"))
    angles = [float(r["angle_deg"]) for r in rows]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    ax.plot(angles, [float(r["reference_nm"]) for r in rows], "k-", linewidth=2, label="reference (biological)")
    ax.plot(angles, [float(r["optimized_nm"]) for r in rows], "C0-",
            label=f"optimized at {summary['pressure_kpa']:g} kPa")
    if rows and rows[0].get("min_pressure_optimized_nm", "") != "":
        mp = summary.get("min_pressure", {})
        ax.plot(angles, [float(r["min_pressure_optimized_nm"]) for r in rows], "k--",
                label=f"optimized at {mp.get('pressure_kpa', 0):.0f} kPa (minimum pressure)")
    ax.set_xlabel("wrist angle [deg] (flexion +)")
    ax.set_ylabel("flexion torque [N m]")
    ax.grid(alpha=0.3)
    ax.legend()
    save(fig, out, "design_curve.png",
         "Exosuit torque of the optimized placement against the reference (Fig. ParameterOptimizationResult).", plots)


def tracking(run, summary, out, plots):
    rows = read_csv(os.path.join(run, "trials.csv"))
    runs = defaultdict(list)
    for r in rows:
        runs[(r["controller"], r["repetition"])].append(r)
    controllers = []
    for controller, _ in runs:
        if controller not in controllers:
            controllers.append(controller)
    sinusoid = summary.get("trajectory") == "sinusoid"
    for controller in controllers:
        reps = sorted(rep for c, rep in runs if c == controller)
        first = runs[(controller, reps[0])]
        t = [float(r["t_s"]) for r in first]
        fig, axes = plt.subplots(3, 1, figsize=(9, 7.5), sharex=True)
        for axis, name in ((0, "fe"), (1, "ur")):
            ax = axes[axis]
            ax.plot(t, [float(r[f"desired_{name}_deg"]) for r in first], "k-", linewidth=1.5, label="desired")
            for rep in reps:
                series = runs[(controller, rep)]
                ax.plot([float(r["t_s"]) for r in series], [float(r[f"measured_{name}_deg"]) for r in series],
                        linewidth=0.8, label=f"IMU, repetition {rep}")
            ax.set_ylabel(("flexion/extension" if name == "fe" else "ulnar/radial") + " [deg]")
            ax.grid(alpha=0.3)
        axes[0].legend(ncol=4)
        for column, label in (("cmd_flexor_kpa", "flexor"), ("cmd_extensor_kpa", "extensor"),
                              ("cmd_ulnar_kpa", "ulnar"), ("cmd_radial_kpa", "radial")):
            axes[2].plot(t, [float(r[column]) for r in first], linewidth=0.8, label=label)
        axes[2].set_ylabel("commanded pressure [kPa]")
        axes[2].set_xlabel("time [s]")
        axes[2].grid(alpha=0.3)
        axes[2].legend(ncol=4)
        save(fig, out, f"tracking_{controller}.png",
             f"{controller} controller: desired and IMU angles of every repetition, and the commanded pressures of "
             f"repetition {reps[0]}.", plots)
        if sinusoid:
            fig, ax = plt.subplots(figsize=(5.5, 5))
            ax.plot([float(r["desired_fe_deg"]) for r in first], [float(r["desired_ur_deg"]) for r in first], "k-",
                    linewidth=1.5, label="desired")
            ax.plot([float(r["measured_fe_deg"]) for r in first], [float(r["measured_ur_deg"]) for r in first],
                    linewidth=0.8, label="IMU")
            reach = summary["reachable_range_deg"]
            ax.add_patch(plt.Rectangle((-reach["extension"], -reach["radial"]), reach["extension"] + reach["flexion"],
                                       reach["radial"] + reach["ulnar"], fill=False, linestyle=":",
                                       label="reachable range"))
            ax.set_xlabel("flexion/extension [deg]")
            ax.set_ylabel("ulnar/radial [deg]")
            ax.grid(alpha=0.3)
            ax.legend()
            save(fig, out, f"tracking_plane_{controller}.png",
                 f"{controller} controller in the joint plane (Fig. Demonstration_trajectory), repetition {reps[0]}, "
                 "with the range the exosuit can hold.", plots)


PLOTTERS = {"torque_validation": torque_validation, "range_of_motion": range_of_motion,
            "design_optimization": design_optimization, "tracking": tracking}


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_run.py RUN_DIR OUT_DIR")
    run, out = sys.argv[1], sys.argv[2]
    with open(os.path.join(run, "trials.json")) as f:
        kind = json.load(f)["kind"]
    with open(os.path.join(run, "summary.json")) as f:
        summary = json.load(f)
    if kind not in PLOTTERS:
        sys.exit(f"plot_run.py: no plots for kind '{kind}'")
    os.makedirs(out, exist_ok=True)
    plots = []
    PLOTTERS[kind](run, summary, out, plots)
    with open(os.path.join(out, "plots.json"), "w") as f:
        json.dump(plots, f, indent=1)


if __name__ == "__main__":
    main()

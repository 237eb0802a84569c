#!/usr/bin/env python3
"""Where the independent benchmark's verdicts go wrong, form by form.

Reads the files `softwrist diagnose-bench --generator independent --out FILE` writes (the ones `--merge` reads) and
prints, for each case (a form, a pair or the nominal), how often its verdict was right with the Wilson 95 % interval,
the median size of the effect in noise units, and what the wrong verdicts were. The rates `--merge` prints pool the
forms; this says which forms they come from.

    python3 scripts/benchmark_by_form.py experiments/diagnosis_calibration/reported_seed5[0-5]_*.json
"""
import argparse
import collections
import json
import math
import statistics
import sys


def wilson(successes, n, z=1.959964):
    """The Wilson score interval (the one src/diagnosis_bench/wilson.h gives), as percentages."""
    if n == 0:
        return 0.0, 100.0
    p = successes / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return 100 * max(0.0, centre - half), 100 * min(1.0, centre + half)


def read_runs(paths):
    runs = []
    for path in paths:
        try:
            with open(path, encoding="utf-8") as f:
                summary = json.load(f)
        except (OSError, json.JSONDecodeError) as e:
            sys.exit(f"benchmark_by_form: {path}: {e}")
        if not isinstance(summary, dict) or not isinstance(summary.get("runs"), list):
            sys.exit(f"benchmark_by_form: {path}: no 'runs' list (not a diagnose-bench --out file)")
        for i, run in enumerate(summary["runs"]):
            missing = [k for k in ("case", "category", "expected", "verdict") if k not in run]
            if missing:
                sys.exit(f"benchmark_by_form: {path}: runs[{i}] lacks {', '.join(missing)}")
            runs.append(run)
    return runs


def wrong_as(run):
    """How a wrong verdict is listed: a pair's with the effect it should have named."""
    verdict = run["verdict"] or "(failed)"
    return f"{verdict} for {run['expected']}" if run["category"] == "pair" else verdict


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="+", help="diagnose-bench --out files")
    args = parser.parse_args()
    by_case = collections.defaultdict(list)
    for run in read_runs(args.files):
        by_case[(run["category"], run["case"])].append(run)
    order = {"none": 0, "single": 1, "outside": 2, "pair": 3}
    print(f"{'case':44} {'right':>10} {'Wilson 95 %':>13} {'median size':>11}  wrong verdicts")
    for (category, case), runs in sorted(by_case.items(), key=lambda kv: (order.get(kv[0][0], 9), kv[0][1])):
        right = sum(1 for r in runs if r["verdict"] == r["expected"] and not r.get("error"))
        low, high = wilson(right, len(runs))
        sizes = [r.get("magnitude_noise_units") for r in runs]
        sizes = [x for x in sizes if isinstance(x, (int, float)) and math.isfinite(x)]
        size = statistics.median(sizes) if sizes else float("nan")
        wrong = collections.Counter(wrong_as(r) for r in runs if r["verdict"] != r["expected"] or r.get("error"))
        wrong_text = ", ".join(f"{verdict} {n}" for verdict, n in wrong.most_common())
        print(f"{case:44} {right:>4} of {len(runs):<2} {low:5.1f}-{high:5.1f} % {size:11.1f}  {wrong_text}")


if __name__ == "__main__":
    main()

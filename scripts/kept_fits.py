#!/usr/bin/env python3
"""One catalogue effect's single fit in each kept diagnosis, beside the truth it was fitted to.

For each kept data set (diagnose-bench --keep DIR: DIR/<case>-<seed>/diagnosis.json and data/truth.json), prints the
verdict, the effect's fitted parameters, the share of the held-out error it closed alone with its bootstrap interval,
the base it was fitted from, and the truth's forms with their parameters. It shows what a verdict rule could use
that the shares do not: an IMU latency fitted close to the truth while closing 1 % of the error, or the same effect
fitted at exactly zero on the nominal device.

  python3 scripts/kept_fits.py --effect imu_bias [--case latency_jitter --case none] DIR [DIR ...]
"""
import argparse
import glob
import json
import os
import sys


def load(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"kept_fits: {path}: {e}")


def number(value, spec):
    """A JSON number as `spec` formats it; null (a NaN the diagnosis wrote) as "null"."""
    return format(value, spec) if isinstance(value, (int, float)) else "null"


def truth_text(data_set):
    path = os.path.join(data_set, "data", "truth.json")
    if not os.path.exists(path):
        return "(no truth.json)"
    forms = [e.get("form", "?") + " " + json.dumps(e.get("parameters", {}), sort_keys=True)
             for e in load(path).get("effects", [])]
    return "; ".join(forms) or "none"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--effect", required=True, help="a catalogue effect, e.g. imu_bias")
    parser.add_argument("--case", action="append", default=[], dest="cases",
                        help="only data sets whose case starts with this (repeatable)")
    parser.add_argument("dirs", nargs="+", help="diagnose-bench --keep directories")
    args = parser.parse_args()
    found = 0
    for directory in args.dirs:
        for path in sorted(glob.glob(os.path.join(directory, "*", "diagnosis.json"))):
            data_set = os.path.dirname(path)
            case = os.path.basename(data_set)
            if args.cases and not any(case.startswith(c) for c in args.cases):
                continue
            diagnosis = load(path)
            fits = [e for e in diagnosis.get("effects", []) if e.get("name") == args.effect]
            if not fits or not fits[0].get("applicable", True):
                print(f"{case}: verdict {diagnosis.get('verdict')}, no {args.effect} fit" +
                      (" (it acts on none of the trials)" if fits else ""))
                continue
            fit = fits[0]
            params = ", ".join(f"{k} {number(v, '.4g')}" for k, v in sorted(fit.get("params", {}).items()))
            base = "within tolerances" if fit.get("within_tolerances") else "as placed"
            print(f"{case}: verdict {diagnosis.get('verdict')}; {args.effect} {params}; closes "
                  f"{number(fit.get('shrink_fraction'), '.4f')} ({number(fit.get('ci_low'), '.4f')} to "
                  f"{number(fit.get('ci_high'), '.4f')}) "
                  f"from the nominal {base}; truth: {truth_text(data_set)}")
            found += 1
    if found == 0:  # every data set read says so above; a status for scripts
        sys.exit(f"kept_fits: no kept diagnosis with a {args.effect} fit under {' '.join(args.dirs)}")


if __name__ == "__main__":
    main()

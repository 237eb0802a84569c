#!/usr/bin/env python3
"""For each kept diagnosis.json (diagnose-bench --keep DIR: DIR/<case>-<seed>/diagnosis.json), the tolerances the
nominal's fit pinned at an edge of their box whose own effect, fitted alone, went beyond the fitted value there (the
rule compares with the box's edge itself, which the fitted value is within 2 % of the box's width of), and the share
of the held-out error that effect closed (the pinned-tolerance rule, diagnosis.cc effect_beyond_pinned_tolerance).

  python3 scripts/pinned_edges.py [--json] DIR [DIR ...]
"""
import glob
import json
import os
import sys


def pinned_beyond(diagnosis):
    tolerance = diagnosis.get("tolerance") or {}
    at_bound = set(tolerance.get("at_bound", []))
    fitted = tolerance.get("fitted", {})
    moved = tolerance.get("moved_fraction", {})
    found = []
    for effect in diagnosis.get("effects", []):
        if not effect.get("applicable", True):
            continue
        for parameter, value in effect.get("params", {}).items():
            name = effect["name"] + "." + parameter
            if name not in at_bound:
                continue
            edge = fitted[name]
            beyond = value < edge if moved[name] < 0 else value > edge
            if beyond:
                found.append({"parameter": name, "edge": edge, "effect_value": value,
                              "shrink_fraction": effect["shrink_fraction"], "extended": effect.get("extended", False)})
    return found


def main(argv):
    as_json = "--json" in argv
    dirs = [a for a in argv if a != "--json"]
    if not dirs:
        sys.exit(__doc__)
    rows = []
    for d in dirs:
        files = sorted(glob.glob(os.path.join(d, "*", "diagnosis.json")))
        if not files:
            sys.exit(f"pinned_edges: no <case>/diagnosis.json under {d}")
        for f in files:
            with open(f) as handle:
                diagnosis = json.load(handle)
            rows.append({"data_set": os.path.basename(os.path.dirname(f)), "verdict": diagnosis["verdict"],
                         "pinned_beyond": pinned_beyond(diagnosis)})
    if as_json:
        print(json.dumps(rows, indent=1))
        return
    for r in rows:
        cells = [f"{p['parameter']} {p['edge']:.4g}->{p['effect_value']:.4g} closes {p['shrink_fraction']:.2f}"
                 + (" (extended)" if p["extended"] else "") for p in r["pinned_beyond"]]
        print(f"{r['data_set']:40s} {r['verdict']:14s} " + " | ".join(cells))


if __name__ == "__main__":
    main(sys.argv[1:])

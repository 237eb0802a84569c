#!/usr/bin/env python3
"""For each kept diagnosis.json (diagnose-bench --keep DIR: DIR/<case>-<seed>/diagnosis.json), the tolerances the
nominal's fit pinned at an edge of their box whose own effect, fitted alone, went beyond the fitted value there (the
rule compares with the box's edge itself, which the fitted value is within 2 % of the box's width of), and the share
of its base's held-out error that effect closed where it acts ("shrink_where_acting", where the diagnosis recorded it;
otherwise "shrink_fraction") (the pinned-tolerance rule, diagnosis.cc effect_beyond_pinned_tolerance).
With --absorbed, also the verdict diagnosis.cc's name_absorbed_larger gives where the verdict names the combination's
leader: the pinned effect (in its base form, closing pair_share, a member of the combination) that closes more of its
base's held-out error than the leader's single fit closes of its own (for diagnoses kept by builds before that rule;
the fitted value stands for the box's edge, as above; pair_share at its calibrated 0.2). An extended fit is read in the
base form it replaced ("base_form"), where the diagnosis recorded it.

  python3 scripts/pinned_edges.py [--json] [--absorbed] DIR [DIR ...]
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
        # An extended fit is read in the base form it replaced, where the diagnosis recorded it (EffectFit::base_form);
        # one kept by an older build is listed, marked extended, and passed over by --absorbed.
        base_form = effect.get("base_form") if effect.get("extended", False) else None
        read = base_form or effect
        for parameter, value in read.get("params", {}).items():
            name = effect["name"] + "." + parameter
            if name not in at_bound:
                continue
            edge = fitted[name]
            beyond = value < edge if moved[name] < 0 else value > edge
            if beyond:
                found.append({"parameter": name, "edge": edge, "effect_value": value,
                              # Its share where it acts (EffectFit::shrink_where_acting), where recorded.
                              "shrink_fraction": read.get("shrink_where_acting", read["shrink_fraction"]),
                              "extended": effect.get("extended", False) and base_form is None,
                              "base_form": base_form is not None})
    return found


PAIR_SHARE = 0.2  # DiagnosisOptions::pair_share, the calibrated setting


def absorbed_larger(diagnosis, pinned):
    """The verdict name_absorbed_larger gives: the pinned effect where it closes more than the named one."""
    verdict = diagnosis["verdict"]
    members = [e["name"] for e in diagnosis.get("combination", [])]
    named = next((e for e in diagnosis.get("effects", []) if e["name"] == verdict), None)
    eligible = [p for p in pinned if not p["extended"] and p["shrink_fraction"] >= PAIR_SHARE]
    if not members or verdict != members[0] or diagnosis.get("beyond_tolerance") or named is None or not eligible:
        return verdict
    best = max(eligible, key=lambda p: p["shrink_fraction"])  # the first of equals, as diagnosis.cc
    effect = best["parameter"].split(".")[0]
    named_share = named.get("shrink_where_acting", named["shrink_fraction"])
    return effect if effect in members and best["shrink_fraction"] > named_share else verdict


def main(argv):
    as_json = "--json" in argv
    absorbed = "--absorbed" in argv
    dirs = [a for a in argv if a not in ("--json", "--absorbed")]
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
            pinned = pinned_beyond(diagnosis)
            rows.append({"data_set": os.path.basename(os.path.dirname(f)), "verdict": diagnosis["verdict"],
                         "pinned_beyond": pinned})
            if absorbed:
                rows[-1]["absorbed_larger"] = absorbed_larger(diagnosis, pinned)
    if as_json:
        print(json.dumps(rows, indent=1))
        return
    for r in rows:
        cells = [f"{p['parameter']} {p['edge']:.4g}->{p['effect_value']:.4g} closes {p['shrink_fraction']:.2f}"
                 + (" (extended)" if p["extended"] else "") + (" (base form)" if p.get("base_form") else "")
                 for p in r["pinned_beyond"]]
        changed = f" -> {r['absorbed_larger']}" if r.get("absorbed_larger", r["verdict"]) != r["verdict"] else ""
        print(f"{r['data_set']:40s} {r['verdict']:14s}{changed} " + " | ".join(cells))


if __name__ == "__main__":
    main(sys.argv[1:])

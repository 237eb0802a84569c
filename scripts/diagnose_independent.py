#!/usr/bin/env python3
"""The diagnosis on data it did not generate: data sets from the independent generator (softwrist generate), each
file imported with what its manifest states (kind, muscle, posture, what the sweep's torque includes, angles zeroed at
the start, the angle sensor's resolution, and the rig: the torque rig's placement or the prototype's), diagnosed in
one run, each verdict beside the truth. A step towards the independent benchmark (issue 20), not the benchmark.

  python3 scripts/diagnose_independent.py --softwrist build/release/src/cli/softwrist --out /tmp/indep \
      [--seeds 1,2] [--forms none,slow_vent,...] [--trajectory-s 24] [--unstated]

--unstated imports as before the conventions could be stated (kind, hand supported, muscle; one placement), for a
comparison. Prints one line per data set and the fraction right with its Wilson 95 % interval; writes
OUT/results.json.
"""
import argparse
import json
import math
import pathlib
import subprocess
import sys


def wilson(k, n, z=1.96):
    if n == 0:
        return (0.0, 1.0)
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (max(0.0, centre - half), min(1.0, centre + half))


def run(args, log):
    with open(log, 'w') as out:
        return subprocess.run(args, stdout=out, stderr=subprocess.STDOUT).returncode


# The independent device's two rigs as its owner would describe them (experiments/independent_device/README.md):
# the torque rig of Table torque_measurement_parameters (its flexor; the tensile test is of that fPAM) and the
# prototype of Table RoM.
RIGS = {'torque_rig': 'experiments/independent_device/torque_rig.json',
        'prototype': 'experiments/independent_device/prototype.json'}


def import_args(entry, unstated):
    """What the manifest entry states, as import options."""
    if unstated:
        args = ['--hand-supported'] if entry.get('posture') == 'hand_supported' else []
        return args + (['--muscle', entry['muscle']] if 'muscle' in entry else [])
    args = ['--model', RIGS[entry['rig']]]
    if 'posture' in entry:
        args += ['--posture', entry['posture']]
    if 'muscle' in entry:
        args += ['--muscle', entry['muscle']]
    if 'torque_includes' in entry:
        args += ['--torque-includes', entry['torque_includes']]
    if entry.get('angles_zeroed_at_start'):
        args.append('--angles-zeroed')
    if 'angle_resolution_deg' in entry:
        args += ['--angle-resolution-deg', str(entry['angle_resolution_deg'])]
    return args


def expected_label(truth):
    labels = truth['labels']
    return 'unexplained' if labels[0].startswith('outside:') else labels[0]


def one_case(sw, out, form, seed, model, trajectory_s, unstated):
    case = out / f'{form}-{seed}'
    data, real, diag = case / 'data', case / 'real', case / 'diagnosis'
    generate = [sw, 'generate', '--out', str(data), '--seed', str(seed), '--trajectory-s', str(trajectory_s)]
    if form != 'none':
        generate += ['--effect', form]
    if run(generate, case.with_suffix('.generate.log')) != 0:
        return {'form': form, 'seed': seed, 'error': 'generate failed'}
    manifest = json.loads((data / 'manifest.json').read_text())
    truth = json.loads((data / 'truth.json').read_text())
    for entry in manifest['files']:
        name = entry['csv'].rsplit('.', 1)[0]
        args = [sw, 'import', '--kind', entry['kind'], str(data / entry['csv']), '--out', str(real / name),
                '--overwrite'] + import_args(entry, unstated)
        if run(args, case.with_suffix(f'.import_{name}.log')) != 0:
            return {'form': form, 'seed': seed, 'error': f'import of {entry["csv"]} failed'}
    if run([sw, 'diagnose', '--real', str(real), '--model', model, '--out', str(diag), '--no-plots'],
           case.with_suffix('.diagnose.log')) != 0:
        return {'form': form, 'seed': seed, 'error': 'diagnose failed'}
    d = json.loads((diag / 'diagnosis.json').read_text())
    return {'form': form, 'seed': seed, 'expected': expected_label(truth), 'verdict': d['verdict'],
            'leading_effect': d.get('leading_effect'), 'explained_fraction': d.get('explained_fraction'),
            'gap_closed': d.get('gap_closed'), 'magnitude_noise_units': truth['magnitude_noise_units'],
            'conventions': truth['conventions'],
            'gaps': {t['experiment']: round(t.get('excess_nominal', float('nan')), 2) for t in d['trials']}}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--softwrist', required=True)
    parser.add_argument('--out', required=True)
    parser.add_argument('--seeds', default='1')
    parser.add_argument('--forms', default='')
    parser.add_argument('--model', default=RIGS['prototype'])
    parser.add_argument('--trajectory-s', type=float, default=24.0)
    parser.add_argument('--unstated', action='store_true', help='import without the manifest\'s conventions')
    a = parser.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    forms = [f for f in a.forms.split(',') if f]
    if not forms:
        listing = subprocess.run([a.softwrist, 'generate', '--list-forms'], capture_output=True, text=True, check=True)
        forms = [line.split()[0] for line in listing.stdout.splitlines() if line.strip()]
    results = []
    for seed in [int(s) for s in a.seeds.split(',')]:
        for form in forms:
            r = one_case(a.softwrist, out, form, seed, a.model, a.trajectory_s, a.unstated)
            results.append(r)
            if 'error' in r:
                print(f"{form:<24} seed {seed}: {r['error']}", flush=True)
            else:
                mark = 'right' if r['verdict'] == r['expected'] else 'WRONG'
                print(f"{form:<24} seed {seed}: expected {r['expected']:<14} verdict {r['verdict']:<14} {mark} "
                      f"(largest effect {r['magnitude_noise_units']:.1f} noise units; leading "
                      f"{r['leading_effect'] or '-'} {100 * (r['explained_fraction'] or 0):.0f} %; nominal gaps "
                      f"{r['gaps']})", flush=True)
    done = [r for r in results if 'error' not in r]
    right = sum(r['verdict'] == r['expected'] for r in done)
    low, high = wilson(right, len(done))
    print(f'diagnose_independent: {right} of {len(done)} verdicts right ({100 * right / max(1, len(done)):.0f} %, '
          f'Wilson 95 % interval {100 * low:.0f}-{100 * high:.0f} %); {len(results) - len(done)} failed to run')
    (out / 'results.json').write_text(json.dumps({'results': results, 'right': right, 'cases': len(done),
                                                  'wilson95': [low, high]}, indent=2) + '\n')
    return 0


if __name__ == '__main__':
    sys.exit(main())

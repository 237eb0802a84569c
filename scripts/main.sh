#!/usr/bin/env bash
# The main job: set-up, build, and the default experiments with their results, written to out/main/:
#   the analytic model's tables (flexor torque three ways; modeled range of motion beside the paper's),
#   the paper's experiments in simulation (torque validation, range of motion, design optimization with the
#   minimum-pressure search; planar steps and spatial tracking with the paper's and the model-based controller),
#   each a run directory with its trial log, summary.json and an HTML report (report/index.html, with plots and
#   renders of the run's moments), two offscreen renders of the paper's device, and a video of the model-based
#   controller on the planar steps (4x real time), and a rehearsed hardware trial (the bridge against the device
#   emulator with a real device's effects) beside its simulation, the calibration of that emulated device from its own
#   sensors (out/main/calibration/calibrated.json) and the planar steps with the model-based controller given it.
#   bash scripts/main.sh                    builds build/release (Release) and runs the job
#   bash scripts/main.sh --build-dir DIR    runs it with the softwrist of an existing build tree instead (DIR absolute
#                                           or relative to the repository; CI: the test build, the same sources at
#                                           -O2: a third build would add five minutes to CI and test nothing new)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/release
if [ "${1:-}" = "--build-dir" ] && [ -n "${2:-}" ] && [ $# -eq 2 ]; then
  [ -f "$2/CMakeCache.txt" ] || { echo "main.sh: $2 is not a configured build tree" >&2; exit 2; }
  build=$(cd "$2" && pwd)
elif [ $# -gt 0 ]; then
  echo "usage: $0 [--build-dir DIR]" >&2
  exit 2
fi
bash scripts/setup.sh
if [ "$build" = build/release ]; then
  cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DSOFTWRIST_BUILD_TESTS=OFF >/dev/null
fi
cmake --build "$build" -j2 --target softwrist softwrist_fpam
softwrist="$build/src/cli/softwrist"
"$softwrist" model tables --out out/main
for experiment in torque_validation range_of_motion design_optimization planar_tracking spatial_tracking; do
  "$softwrist" run "experiments/$experiment.json" --out "out/main/$experiment" --jobs 2 --quiet --overwrite
  "$softwrist" report "out/main/$experiment"
done
"$softwrist" render --fe-deg 30 --pressures-kpa 137,10,0,0 --view radial --out out/main/flexor_137kpa_radial.png
"$softwrist" render --ur-deg 15 --pressures-kpa 0,0,137,20 --view palmar --out out/main/ulnar_137kpa_palmar.png
# Case 3: the model-based controller's first repetition (cases: the paper's controller x3, then model-based x3).
"$softwrist" render --run out/main/planar_tracking --video out/main/planar_tracking/model_based_steps.mp4 --case 3 \
  --speed 4 --width 480 --height 360
# A rehearsal of a hardware trial: the short planar steps through the bridge against the device emulator with a
# real device's effects (experiments/emulator/realistic.json), beside the same experiment in simulation. The
# emulator and the host share one simulated clock (--emulator), so the result is the same however busy the machine
# is; `softwrist emulate` + `trial --device` is the same rehearsal in real time over a pseudo-terminal.
"$softwrist" trial experiments/planar_rehearsal.json --emulator experiments/emulator/realistic.json \
  --out out/main/rehearsal_trial --overwrite
"$softwrist" run experiments/planar_rehearsal.json --out out/main/rehearsal_sim --quiet --overwrite
"$softwrist" report out/main/rehearsal_trial
"$softwrist" report out/main/rehearsal_sim
# Calibration (docs/calibration.md): the excitation routine on the same emulated device, the fit of what its sensors
# identify, and the planar steps with the model-based controller given the calibrated placement.
"$softwrist" calibrate --emulator experiments/emulator/realistic.json --placement models/rom_device.json \
  --out out/main/calibration --overwrite
"$softwrist" trial experiments/planar_tracking.json --emulator experiments/emulator/realistic.json \
  --controller model_based --repetitions 1 --model out/main/calibration/calibrated.json \
  --out out/main/calibrated_trial --overwrite
"$softwrist" report out/main/calibrated_trial
# The gap diagnosis on the paper's case: "real" data from the paper's device (whose mounts stretch), diagnosed against
# a nominal model that leaves the stretching out (models/paper_device_rigid_mounts.json).
rm -rf out/main/diagnosis_real
"$softwrist" synthesize --model models/paper_device.json --out out/main/diagnosis_real --trajectory-s 72
"$softwrist" diagnose --real out/main/diagnosis_real --model models/paper_device_rigid_mounts.json \
  --out out/main/diagnosis

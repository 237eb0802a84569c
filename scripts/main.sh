#!/usr/bin/env bash
# The main job: set-up, build, and the default experiment's output. For now that is the analytic model's tables
# (flexor torque at the paper's angles and pressures, three ways; modeled range of motion beside the paper's) and
# two offscreen renders of the paper's device in MuJoCo, written to out/main/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DSOFTWRIST_BUILD_TESTS=OFF >/dev/null
cmake --build build/release -j2 --target softwrist softwrist_fpam
softwrist=./build/release/src/cli/softwrist
$softwrist model tables --out out/main
$softwrist render --fe-deg 30 --pressures-kpa 137,10,0,0 --view radial --out out/main/flexor_137kpa_radial.png
$softwrist render --ur-deg 15 --pressures-kpa 0,0,137,20 --view palmar --out out/main/ulnar_137kpa_palmar.png

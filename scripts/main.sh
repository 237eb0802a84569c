#!/usr/bin/env bash
# The main job: set-up, build, and the default experiment's output. For now that is the analytic model's tables
# (flexor torque at the paper's angles and pressures, three ways; modeled range of motion beside the paper's),
# written to out/main/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release -DSOFTWRIST_BUILD_TESTS=OFF >/dev/null
cmake --build build/release -j2 --target softwrist
./build/release/src/cli/softwrist model tables --out out/main

#!/usr/bin/env bash
# Installs softwrist's build and run dependencies, all from Debian 12 packages. Quick (no apt-get at all) when
# every package is already installed. Run as root or with sudo available.
#   bash scripts/setup.sh          build and run dependencies
#   bash scripts/setup.sh --tests  also what only the tests use: a headless browser and a virtual X display
set -euo pipefail

packages=(
  build-essential cmake           # toolchain: g++ 12, CMake 3.25
  libmujoco-dev libqhull-dev      # MuJoCo 2.2.2 (its CMake config needs the qhull headers)
  libeigen3-dev                   # linear algebra
  libnlopt-cxx-dev                # design optimization
  libglfw3-dev libosmesa6-dev     # interactive viewer, headless rendering
  libpng-dev                      # PNG output of renders
  libcli11-dev                    # command line
  nlohmann-json3-dev              # JSON configs and results
  libfmt-dev                      # formatting
  libboost-dev                    # Boost.Math (header-only): F and chi-squared tests of the gap diagnosis
  libsimavr-dev libelf-dev        # the firmware in the loop: a simulated ATmega328P (softwrist hil, docs/hil.md)
  libgtest-dev libgmock-dev       # tests
  libbenchmark-dev                # benchmarks
  python3-matplotlib              # report plots (softwrist report)
  ffmpeg                          # videos of tracking runs (softwrist render --video); optional at run time
)
if [ "${1:-}" = "--tests" ]; then
  packages+=(
    chromium                      # the report opened in a headless browser
    xvfb xauth libgl1-mesa-dri    # the GLFW viewer on a virtual display (xvfb-run), drawn by Mesa
    gcc-avr binutils-avr avr-libc arduino-core-avr  # the Arduino Uno firmware, compiled so that it cannot rot
    clang-14 libclang-rt-14-dev   # the sanitizer build and the fuzz targets: ASan + UBSan, libFuzzer (scripts/fuzz.sh)
    lld                           # LLVM's linker (ld.lld), for those clang builds
    clang-format-14               # the C++ style check (scripts/check_format.sh)
    slurmctld slurmd slurm-client munge  # a one-node Slurm for the cluster scripts' test (scripts/slurm/selftest.sh)
  )
elif [ -n "${1:-}" ]; then
  echo "usage: $0 [--tests]" >&2
  exit 2
fi

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if ((${#missing[@]} == 0)); then
  echo "setup: all ${#packages[@]} Debian packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "setup: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"

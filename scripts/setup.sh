#!/usr/bin/env bash
# Installs softwrist's build and run dependencies, all from Debian 12 packages. Quick (no apt-get at all) when
# every package is already installed. Run as root or with sudo available.
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
  libgtest-dev libgmock-dev       # tests
  libbenchmark-dev                # benchmarks
  python3-matplotlib              # report plots (softwrist report)
)

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

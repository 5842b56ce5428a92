#!/usr/bin/env bash
# Installs the Debian 12 packages mocaplabel builds and tests with, only those that are missing.
# Idempotent and quiet when everything is there; needs root or sudo when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  # the linker CMakeLists.txt picks when present (GNU ld is several times slower on these static libraries)
  lld
  libeigen3-dev nlohmann-json3-dev libyaml-cpp-dev libcli11-dev
  libspdlog-dev libfmt-dev
  libopencv-dev libopenexr-dev zlib1g-dev libdeflate-dev libxxhash-dev libassimp-dev libnanoflann-dev
  libegl-dev libgles-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  libusb-1.0-0-dev libfreenect-dev libcpp-httplib-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev
  # the validator benchmarks' baselines: PCL's and Open3D's ICP (bench/ only)
  libpcl-dev libopen3d-dev
  # src/calibrate: ChArUco detection (OpenCV contrib aruco) and the camera-mount refinement (Ceres)
  libopencv-contrib-dev libceres-dev
  # the one-node Slurm cluster of the Slurm executor's tests (scripts/slurm-cluster.sh, docs/slurm-test-cluster.md)
  munge slurmctld slurmd slurm-client
  # the capture daemon's live page test (tests/capture/browser): Debian's browser, driven headless by
  # playwright-core from npm (installed by the test's set-up from the committed lock file)
  chromium
)
# node and npm from Debian, unless a node (e.g. NodeSource's, which bundles npm) is there already
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
if [[ $(id -u) -eq 0 ]]; then
  sudo_cmd=()
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  sudo_cmd=(sudo -n)
else
  echo "install-deps: missing Debian packages: ${missing[*]}" >&2
  echo "install-deps: run as root, or with sudo, or install them by hand: apt-get install ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
# munge, slurmctld and slurmd would start their system services from their maintainer scripts (invoke-rc.d;
# without systemd that fails): a policy-rc.d answering 101 forbids it while we install, if there is none.
if [[ ! -e /usr/sbin/policy-rc.d ]]; then
  printf '#!/bin/sh\nexit 101\n' | "${sudo_cmd[@]}" tee /usr/sbin/policy-rc.d >/dev/null
  "${sudo_cmd[@]}" chmod 755 /usr/sbin/policy-rc.d
  trap '"${sudo_cmd[@]}" rm -f /usr/sbin/policy-rc.d' EXIT
fi
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null

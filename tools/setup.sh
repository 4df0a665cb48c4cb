#!/usr/bin/env bash
# Installs the Debian 12 packages caustica builds and runs with, if missing.
# As root it runs apt-get; otherwise it prints the exact command to run.
#   tools/setup.sh            everything: the renderer's, the tests' and
#                             benchmarks', gnuplot, the Python module's
#                             (python3-dev, pybind11-dev, python3-numpy; for
#                             its tests and examples python3-pytest and
#                             python3-matplotlib)
#   tools/setup.sh --render   the renderer's alone (./caustica render on a
#                             fresh machine: 162 packages, 204 MB to download,
#                             against 298 and 313 MB for everything;
#                             docs/howto.md, "Build and test time"); OpenMPI
#                             is among them (41 packages, 24 MB), so the
#                             first binary already runs under mpirun
#   tools/setup.sh --fuzz     what tools/fuzz.sh builds the fuzz targets with
#   tools/setup.sh --oclgrind everything, and the simulator tools/oclgrind.sh
#                             runs the tests on
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-clhpp-headers opencl-c-headers clinfo
  libglm-dev libstb-dev nlohmann-json3-dev libcli11-dev libtinyexr-dev libtinyobjloader-dev libtinygltf-dev
  openmpi-bin libopenmpi-dev
  libtbb12
)
if [[ ${1:-} != --render ]]; then
  packages+=(
    libgtest-dev libbenchmark-dev
    gnuplot-nox
    python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib
  )
fi
# tools/fuzz.sh: clang with its libFuzzer and sanitizer runtimes (Debian's
# clang-14; libclang_rt.fuzzer-x86_64.a is in libclang-rt-14-dev).
if [[ ${1:-} == --fuzz ]]; then
  packages=(clang libclang-rt-14-dev cmake ninja-build pkg-config
    libglm-dev libstb-dev nlohmann-json3-dev libtinyobjloader-dev libtinygltf-dev libtinyexr-dev libcli11-dev
    ocl-icd-opencl-dev opencl-clhpp-headers opencl-c-headers)
fi
# tools/oclgrind.sh: the default set (it builds and runs the tests) and
# Debian's Oclgrind, a second OpenCL platform that checks kernels.
if [[ ${1:-} == --oclgrind ]]; then
  packages+=(oclgrind)
fi
missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ $status == "install ok installed" ]] || missing+=("$p")
done
# The denoiser's libraries (not a Debian package): tools/fetch_oidn.sh, once,
# after the packages; never fatal.
fetch_oidn() {
  if [[ ${1:-} != --fuzz && ${1:-} != --oclgrind ]]; then
    bash "$(dirname "${BASH_SOURCE[0]}")/fetch_oidn.sh"
  fi
}
if ((${#missing[@]} == 0)); then
  fetch_oidn "${1:-}"
  exit 0
fi
cmd="apt-get install -y --no-install-recommends ${missing[*]}"
if [[ $(id -u) -eq 0 ]]; then
  echo "[setup] installing: ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq >&2
  $cmd >&2
elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
  echo "[setup] installing with sudo: ${missing[*]}" >&2
  sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq >&2
  sudo env DEBIAN_FRONTEND=noninteractive $cmd >&2
else
  echo "[setup] missing Debian packages: ${missing[*]}" >&2
  echo "[setup] run as root:  $cmd" >&2
  exit 1
fi
fetch_oidn "${1:-}"

#!/usr/bin/env bash
# Intel Open Image Denoise for `caustica render --denoise` and `caustica
# denoise`: Debian 12 has no package, so this takes Intel's release binaries
# from PyPI's pinned pyoidn wheel (version and SHA-256 checked), extracts
# only the OIDN libraries into $CAUSTICA_DEPS_DIR (default .deps/ beside
# build/), and leaves the rest of the wheel. CMake finds them there
# (cmake/FindOIDN.cmake) and links them with an RPATH. Their one dependency
# beyond glibc and libstdc++, libtbb.so.12, is Debian's libtbb12
# (tools/setup.sh installs it).
#
# Never fatal: offline, or on a platform without the wheel, it says why on
# stderr and exits 0; caustica then builds without OIDN and `--denoise`
# says how to get it.
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
version=2.5.1
wheel=pyoidn-2.5.1.0-py3-none-manylinux2014_x86_64.whl
sha256=32ad13368f8de1ef63001942ad05b02a00cd732d1206d97f352d3a3f606d823e
deps="${CAUSTICA_DEPS_DIR:-$root/.deps}"
dest="$deps/oidn-$version"
libs=(libOpenImageDenoise.so.$version libOpenImageDenoise_core.so.$version
      libOpenImageDenoise_device_cpu.so.$version libOpenImageDenoise_device_cuda.so.$version)

[[ -f $dest/lib/.complete ]] && exit 0
say() { echo "[setup] OIDN: $*" >&2; }
if [[ $(uname -m) != x86_64 || $(uname -s) != Linux ]]; then
  say "no $wheel for $(uname -s) $(uname -m): building without the denoiser"
  exit 0
fi
if ! python3 -m pip --version >/dev/null 2>&1; then
  if [[ $(id -u) -eq 0 ]]; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends python3-pip >&2 || true
  fi
  if ! python3 -m pip --version >/dev/null 2>&1; then
    say "pip is missing (apt-get install python3-pip): building without the denoiser"
    exit 0
  fi
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
say "fetching pyoidn==$version.0 (Intel's OIDN $version release libraries, ~88 MB) with pip"
if ! python3 -m pip download --quiet --no-deps --only-binary=:all: \
    -d "$tmp" "pyoidn==$version.0" >&2; then
  say "pip could not fetch pyoidn==$version.0 (offline?): building without the denoiser"
  exit 0
fi
if [[ ! -f $tmp/$wheel ]]; then
  say "pip fetched $(ls "$tmp"), not $wheel: building without the denoiser"
  exit 0
fi
got=$(sha256sum "$tmp/$wheel" | cut -d' ' -f1)
if [[ $got != "$sha256" ]]; then
  say "$wheel has SHA-256 $got, expected $sha256: refusing it, building without the denoiser"
  exit 0
fi
mkdir -p "$dest/lib"
if ! python3 - "$tmp/$wheel" "$dest/lib" "${libs[@]}" <<'PY'
import sys, zipfile
wheel, dest, names = sys.argv[1], sys.argv[2], sys.argv[3:]
with zipfile.ZipFile(wheel) as z:
    for name in names:
        with z.open("pyoidn/oidn/lib/" + name) as src, open(dest + "/" + name, "wb") as out:
            out.write(src.read())
PY
then
  say "could not extract the libraries from $wheel: building without the denoiser"
  rm -rf "$dest"
  exit 0
fi
ln -sf libOpenImageDenoise.so.$version "$dest/lib/libOpenImageDenoise.so.2"
ln -sf libOpenImageDenoise.so.2 "$dest/lib/libOpenImageDenoise.so"
echo "$wheel $sha256" > "$dest/lib/.complete"
say "installed in $dest/lib"

#!/usr/bin/env bash
# Runs the kernel-level tests on Oclgrind, a second OpenCL platform that
# simulates the kernels and reports out-of-bounds accesses, reads of
# uninitialised memory and data races (issue 14). Installs Debian's
# oclgrind and registers it as an ICD (/etc/OpenCL/vendors/oclgrind.icd)
# when run as root; caustica then lists it (`caustica devices`) and picks it
# by name only (`--device oclgrind`). Each test runs in its own process
# (Oclgrind can abort at exit after several programs in one process), on
# the device named "oclgrind"; the run fails on a failing test or on any
# error Oclgrind reports. Tests that trace millions of rays or samples are
# left out: Oclgrind interprets every work-item (the photon grid's
# tiny-table test runs out of memory under its race detection).
#   tools/oclgrind.sh [build dir, default build]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build="${1:-$root/build}"
icd=/etc/OpenCL/vendors/oclgrind.icd
if [[ ! -f /usr/lib/oclgrind/liboclgrind-rt-icd.so || ! -f $icd ]]; then
  if [[ $(id -u) -ne 0 ]]; then
    echo "[oclgrind] needs Debian's oclgrind registered as an ICD; as root: apt-get install oclgrind &&" \
      "echo /usr/lib/oclgrind/liboclgrind-rt-icd.so > $icd" >&2
    exit 1
  fi
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends oclgrind >&2
  echo /usr/lib/oclgrind/liboclgrind-rt-icd.so >"$icd"
fi
# Out-of-bounds accesses are always checked; data races on request. Not
# uninitialised reads: Oclgrind 21.10 does not count clEnqueueFillBuffer as
# initialising memory, so every film pass (zeroed that way) would report.
export CAUSTICA_TEST_DEVICE=oclgrind OCLGRIND_DATA_RACES=1
tests=(
  "test_render_core RecordLayout.DeviceAgreesWithHost"
  "test_render_core KernelArgs.BindingIsCheckedAgainstTheKernelsNames"
  "test_render_core Film.HalfBufferHoldsThePassesSinceTheLatestPowerOfTwo"
  "test_render_core Film.NonFiniteAndNegativeAreCountedAndDroppedHugeValuesClamped"
  "test_render_core Film.ScaleKeepsTheHdrRangeOfTheBound"
  "test_render_core Film.AccumulationIsOrderIndependentAndPassesAverage"
  "test_render_core Film.ClearingAPassRangeKeepsFinishedPasses"
  "test_render_core ShadeSurfacePhong.OneStepOnAHandBuiltHit"
  "test_photon_grid PhotonGrid.PhotonsOnCellBordersAndCorners"
  "test_photon_grid PhotonGrid.NoPhotons"
  "test_photon_grid PhotonGrid.AllPhotonsAtOnePoint"
  "test_photon_grid PhotonGrid.SortPutsEveryBucketInIndexOrder"
)
status=0
for entry in "${tests[@]}"; do
  read -r binary filter <<<"$entry"
  log=$(mktemp)
  if "$build/tests/$binary" --gtest_filter="$filter" >"$log" 2>&1 && ! grep -qE "^(Invalid|Uninitialized|Read-write data race|Write-write data race|Work-group divergence)" "$log"; then
    echo "[oclgrind] $filter: clean"
  else
    echo "[oclgrind] $filter: FAILED"
    grep -m 20 -E "Invalid|Uninitialized|race|divergence|FAILED|Failure" "$log" || true
    status=1
  fi
  rm -f "$log"
done
exit $status

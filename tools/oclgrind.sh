#!/usr/bin/env bash
# Runs the test suite's kernels on Oclgrind, a second OpenCL platform that
# simulates them and reports out-of-bounds accesses, reads of uninitialised
# memory and data races (issue 14). Rules: every gtest of build/tests runs,
# each in its own process (Oclgrind can abort at exit after several programs
# in one process), on the device named "oclgrind", two at a time; a test that
# launches no kernel costs only its host time, so nothing has to keep a list
# of which tests are kernel-level. Tests that would trace millions of rays cut
# their counts there with test::sized(); the few left out below say why. The
# run fails on a failing test, on a test past its time limit, or on any error
# line Oclgrind prints.
# CAUSTICA_TEST_SIMULATED_SIZES=1 gives the tests these cut sizes on any
# device: the suite run so on PoCL checks in seconds that the cut assertions
# still hold.
#   tools/oclgrind.sh [build dir, default build] [gtest filter, default all]
# Oclgrind is registered for this run only, through ocl-icd's
# OCL_ICD_VENDORS (a temporary vendors directory), so nothing under /etc is
# written. To make `caustica devices` list it system-wide, as root:
#   echo /usr/lib/oclgrind/liboclgrind-rt-icd.so > /etc/OpenCL/vendors/oclgrind.icd
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build="${1:-$root/build}"
filter="${2:-*}"
jobs=${CAUSTICA_OCLGRIND_JOBS:-2}
# Per test: the slowest (BVH brute-force traversal, the handout scenes in
# phong) take 60-140 s there two at a time on an idle 2-core machine.
limit=${CAUSTICA_OCLGRIND_TEST_SECONDS:-300}

bash "$root/tools/setup.sh" --oclgrind
if [[ ! -f $build/CMakeCache.txt ]]; then
  generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >&2
fi
cmake --build "$build" -j "$(nproc 2>/dev/null || echo 2)" >&2

vendors=$(mktemp -d)
logs=$(mktemp -d)
trap 'rm -rf "$vendors" "$logs"' EXIT
# The system's ICDs stay visible (tests that name another device still find
# it); Oclgrind is added whether or not it is registered there.
cp /etc/OpenCL/vendors/*.icd "$vendors"/ 2>/dev/null || true
echo /usr/lib/oclgrind/liboclgrind-rt-icd.so >"$vendors/oclgrind.icd"
export OCL_ICD_VENDORS=$vendors
# Out-of-bounds accesses are always checked; data races on request. Not
# uninitialised reads (OCLGRIND_UNINITIALIZED=1), whose plugin in Debian 12's
# Oclgrind 21.10 cannot run this suite: it segfaults inside the BSDF test
# kernels and corrupts the heap (glibc "corrupted double-linked list" at
# exit), stops with a fatal error on sincos() into a private variable
# (emit_photons), and calls the result of every atomic_inc on a zeroed
# counter uninitialised (count_bucket_photons: false reports). It also marks
# only the last store of a clEnqueueFillBuffer, or of a copy into part of a
# buffer, as initialised; the runtime fills and copies by kernel on Oclgrind
# for that (Runtime::fill), so CAUSTICA_OCLGRIND_UNINITIALIZED=1 turns the
# check on for a run of chosen tests (a newer Oclgrind may need no more).
# One simulator thread per test: the tests already run two at a time.
export CAUSTICA_TEST_DEVICE=oclgrind OCLGRIND_DATA_RACES=1 OCLGRIND_NUM_THREADS=1
export OCLGRIND_UNINITIALIZED=${CAUSTICA_OCLGRIND_UNINITIALIZED:-0}

# Where Oclgrind 21.10 differs from PoCL without a memory report:
# - dot() is evaluated in double and rounded once (its WorkItemBuiltins.cpp),
#   PoCL sums floats. On a sphere ray near its tangent (half chord 0.02 of
#   the radius) that moved t by 1.3e-5 of itself, within float32's bound
#   there: Intersect.RandomRaysMatchReference now allows that bound.
# - Its compiler prints clang's "N warnings generated." to stderr on a cold
#   build (no program cache): test_cli_errors drops that line here.
# - Its build log gives physical lines of the expanded source (input.cl:312),
#   ignoring #line; the runtime maps them back (map_build_log_lines).
# The host tests (tests/host/, host_*) run no kernel and are not run here.
# Left out, one line each: binary, test, why. Only whole-image statistics
# over many renders, whose kernels the run covers elsewhere (photon pass and
# gather: test_photon_pass, test_photon_grid, stiff_light_limits,
# stiff_caustic_ground, test_caustics_paths, test_community_photons (three
# scenes there) and stiff_determinism's caustics scene; path tracing with MIS: test_path;
# phong over every feature:
# test_official_scenes, test_textures, stiff_invariance).
left_out=(
  "test_caustics Caustics.PhotonMapConvergesToThePathTracedReferenceWithoutDoubleCounting  # convergence slope over 8..256 passes against a reference"
  "test_community_render CommunityCorpus.EveryLoadableSceneRendersInPhong  # the whole community corpus of ../shared rendered in phong, scene after scene"
  "test_error_report ErrorReport.CornellBoxReportsConvergeAndEstimateTheirError  # the error report's Cornell box: MSE against spp at the Monte Carlo rate over many renders and a long reference"
  "test_caustics_error CausticsErrorEstimate.CoversThePhotonMapWithinTwiceTheTrueError  # the photon map's error estimate against the truth, four seeds of 256 passes (its gathers: stiff_caustic_ground, test_caustics_paths, test_community_photons)"
  "test_render_state RenderState.ResumedInProcessPhotonPassHasTheSameBits  # a photon-pass render resumed against an uninterrupted one, 96 passes twice: past 600 s even with one state of each kind (its stages run on the simulator in test_photon_pass and stiff_caustic_ground)"
  "test_render_state RenderState.KilledAndResumedPhotonPassRenderHasTheSameBits  # caustics.json rendered through the CLI, killed with SIGKILL and resumed, against an uninterrupted render: past 300 s (its stages run on the simulator in test_photon_pass and stiff_caustic_ground, state files in the other RenderState tests)"
  "test_directional_light DirectionalLight.PhotonPassFindsTheCausticOfAGlassBall  # full photon maps and their gathers in path mode and phong, twice each: past 300 s (directional photons: DirectionalLight.UnguidedPhotonsCarryItsPower, test_photon_pass; guided disks from infinity: test_phong_sky_caustics)"
)
# The MPI tests run `mpirun` with two and three caustica processes, each
# rendering on the simulator: past the limit (their kernels are the
# one-process renders' above). The one MpiRender test that launches
# nothing (how the shares split) stays.
for name in TwoAndThreeRanksGiveTheBitsOfOneProcess BinaryAndPhongGiveTheBitsOfOneProcess \
  TimeLimitAndTargetErrorAreDecidedForAllRanks ARankThatDiesEndsTheJobWithAClearMessage \
  CheckpointsOfRanksAreOneProcesssStatesAndResumeAfterARankDied PhotonPassSharedByPixelsGivesTheBitsOfOneProcess \
  PhotonPassByPixelsStopsCheckpointsAndResumesAsOneProcess PhotonPassAutoDecidesOnRanksAsInOneProcess \
  WhatRanksCannotDoIsRefused; do
  left_out+=("test_mpi_render MpiRender.$name  # mpirun on the simulator")
done

# Every test as "binary test.name", parameterised ones included.
list=$logs/tests
for binary in "$build"/tests/test_* "$build"/tests/stiff_*; do
  [[ -x $binary && -f $binary ]] || continue
  "$binary" --gtest_list_tests --gtest_filter="$filter" | awk -v b="$(basename "$binary")" '
    /^[^ ]/ { suite = $1 } /^  / { print b, suite $1 }'
done >"$list"
for entry in "${left_out[@]}"; do
  read -r binary name _ <<<"$entry"
  grep -vxF "$binary $name" "$list" >"$list.kept" || true
  mv "$list.kept" "$list"
done

# Oclgrind's messages go to their own log (OCLGRIND_LOG), through a pipe that
# the test and every caustica process it starts append to: a file there
# would be truncated by each process that opens it, and a child's stderr is
# captured by the test that runs it. Any message there fails the test.
run_one() {  # run_one BINARY TEST: prints one result line, fails on a problem
  local binary=$1 name=$2 log=$logs/$1.${2//\//_} start status=0
  start=$(date +%s)
  OCLGRIND_LOG=/dev/fd/3 timeout "$limit" "$build/tests/$binary" --gtest_filter="$name" \
    >"$log.out" 2>&1 3> >(cat >"$log.oclgrind") || status=$?
  wait $! 2>/dev/null || true
  local seconds=$(($(date +%s) - start))
  if ((status == 0)) && ! grep -q '[^[:space:]]' "$log.oclgrind" && ! grep -q "OCLGRIND" "$log.out"; then
    echo "[oclgrind] ${seconds}s $binary $name: clean"
    return 0
  fi
  if ((status == 124)); then
    echo "[oclgrind] ${seconds}s $binary $name: past ${limit}s"
  else
    echo "[oclgrind] ${seconds}s $binary $name: FAILED"
  fi
  grep -E -A3 "OCLGRIND|FAILED|Failure" "$log.out" | head -n 30 || true
  grep -v '^[[:space:]]*$' "$log.oclgrind" | head -n 40 || true
  return 1
}
export -f run_one
export build logs limit
start=$(date +%s)
status=0
xargs -P "$jobs" -L 1 bash -c 'run_one "$0" "$1"' <"$list" || status=1
echo "[oclgrind] $(wc -l <"$list") tests, ${#left_out[@]} left out, $(($(date +%s) - start))s"
exit $status

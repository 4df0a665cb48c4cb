#!/usr/bin/env bash
# Writes tests/test_costs.cmake, the COST of every test that took 2 s or
# more in the last ctest run of a build directory (its
# Testing/Temporary/CTestCostData.txt): `ctest -j` starts the costly tests
# first, so two long tests never end the run alone on a fresh clone, which
# has no cost data of its own yet (docs/howto.md, "Test time"). Run it after
# a full ctest run with cold kernel caches when tests change much:
#   tools/test_costs.sh [build dir, default build]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build="${1:-$root/build}"
data="$build/Testing/Temporary/CTestCostData.txt"
[[ -f $data ]] || { echo "test_costs: no $data (run ctest in $build first)" >&2; exit 1; }
out="$root/tests/test_costs.cmake"
{
  echo "# Written by tools/test_costs.sh from a ctest run (seconds per test, cold kernel"
  echo "# caches, 2 cores): included by ctest after the discovered tests"
  echo "# (tests/CMakeLists.txt), so that ctest -j starts the costly ones first. A name"
  echo "# no test has (a test renamed, the Python tests without pytest) is ignored."
  awk 'NF == 3 && $3 >= 2.0 { printf "%s %.0f\n", $1, $3 }' "$data" | sort -k2,2nr -k1,1 |
    while read -r name cost; do
      printf 'set_tests_properties("%s" PROPERTIES COST %s)\n' "$name" "$cost"
    done
} >"$out"
echo "test_costs: $(grep -c set_tests_properties "$out") tests in $out" >&2

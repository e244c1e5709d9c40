#!/usr/bin/env bash
# Set up (scripts/setup.sh), then run every test: C++ unit tests (ctest, 1 and 2 ranks),
# pytest serial, pytest under mpirun -n 2.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$here/scripts/setup.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export PYTHONPATH="$here/python${PYTHONPATH:+:$PYTHONPATH}"
cd "$here"
echo "== C++ unit tests (ctest)"
ctest --test-dir build --output-on-failure
echo "== pytest, serial (two test processes: pytest-xdist)"
# a temporary tree of its own: pytest's default one (/tmp/pytest-of-$USER) keeps the last three
# runs' folders and deletes older ones, those of another test run going on at the same time too
basetemp="$(mktemp -d "${TMPDIR:-/tmp}/slidebeam-tests.XXXXXX")"
trap 'rm -rf "$basetemp"' EXIT
# each test runs one model on one rank; two at a time keep both cores busy. The tests that start
# an mpirun of their own run after them, one at a time: beside another test their ranks starve
/usr/bin/python3 -m pytest -q -p no:cacheprovider -n 2 --durations=20 --basetemp "$basetemp/serial" \
    -m "not spawns_ranks" tests/python
echo "== pytest, the tests that start their own mpirun (one at a time)"
/usr/bin/python3 -m pytest -q -p no:cacheprovider --durations=10 --basetemp "$basetemp/ranks" \
    -m spawns_ranks tests/python
echo "== pytest, mpirun -n 2"
mpirun -n 2 /usr/bin/python3 -m pytest -q -p no:cacheprovider tests/python
echo "== all tests passed"

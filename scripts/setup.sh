#!/usr/bin/env bash
# Set up on Debian 12: install what is missing (apt-get), then configure and build.
# Idempotent: a second run only rebuilds what changed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
packages=(petsc-dev python3-petsc4py python3-mpi4py python3-meshio python3-h5py python3-numpy python3-pytest
          python3-pytest-xdist python3-matplotlib libeigen3-dev libhdf5-openmpi-dev openmpi-bin pybind11-dev python3-pybind11
          libgtest-dev cmake g++ make pkg-config ccache
          python3-venv python3-setuptools python3-wheel  # these three: pip install (docs/install.md)
          libopenblas0-serial)  # BLAS and LAPACK for SuperLU and MUMPS (Debian's alternatives; one thread a rank)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
# Optional: ParaView's Python module, so that the tests open our XDMF with ParaView's own reader
# (they are skipped without it). A failure here is not fatal.
if ! dpkg-query -W -f='${Status}' python3-paraview 2>/dev/null | grep -q "install ok installed"; then
  sudo_cmd=""
  [ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
  echo "setup: installing python3-paraview (optional)"
  { $sudo_cmd apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq \
      --no-install-recommends python3-paraview >/dev/null; } ||
    echo "setup: python3-paraview not installed; the ParaView test will be skipped"
fi
# Debian's petsc4py imports only under /usr/bin/python3: pin it.
cmake -S "$here" -B "$here/build" -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
# the build's own messages without the progress lines; a failed build fails the set-up
build_log=$(mktemp)
if ! cmake --build "$here/build" -j"$(nproc)" >"$build_log" 2>&1; then
  grep -vE "^(\[|lto-wrapper|gmake)" "$build_log" >&2
  rm -f "$build_log"
  echo "setup: the build failed (messages above)" >&2
  exit 1
fi
grep -vE "^(\[|lto-wrapper|gmake)" "$build_log" || true
rm -f "$build_log"
echo "setup: built $here/build and python/slidebeam/_core"

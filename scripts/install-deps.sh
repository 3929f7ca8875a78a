#!/usr/bin/env bash
# Installs the Debian 12 packages cdpile needs, if any are missing. As root it runs
# apt-get; otherwise it prints the one sudo line to run and exits 1.
set -euo pipefail
packages=(
  g++ cmake make pkg-config          # toolchain (CMake >= 3.25 for the presets)
  libeigen3-dev                      # Eigen 3.4: vectors, sparse matrices, fits
  libsuitesparse-dev                 # KLU: the sparse LU of --solver newton (cd/face_newton.cpp)
  libhdf5-dev hdf5-tools             # HDF5 1.10 C library; h5dump and h5diff for tests
  libcgal-dev                        # CGAL 5.5: neighbour queries for localnu
  libboost-program-options-dev       # the command-line layer
  libgtest-dev                       # unit tests
  libbenchmark-dev                   # micro-benchmarks
  python3 python3-numpy python3-h5py python3-matplotlib python3-scipy  # the pipelines' scripts (pipelines/cdpile_py)
  ffmpeg                             # make -C pipelines movie: a video of a run (pipelines/pile.py)
  util-linux                         # script(1), used by one test of terminal output
  python3-paraview xvfb              # ParaView's Python and a virtual X display: the to-xdmf test
  gnuplot-nox                        # the docs' gnuplot recipes, run by tests/tools/docs/gnuplot_recipes.sh
  slurm-wlm munge                    # a one-node Slurm cluster on localhost: the test
                                     # pipelines/slurm_cluster (docs/cluster.md)
  clang libclang-rt-14-dev           # libFuzzer and clang's sanitizer runtimes: the asan and fuzz presets (docs/fuzzing.md)
)
missing=()
for p in "${packages[@]}"; do
  if [[ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" != "install ok installed" ]]; then
    missing+=("$p")
  fi
done
if [[ ${#missing[@]} -eq 0 ]]; then
  echo "setup: all Debian packages present"
  exit 0
fi
if [[ $(id -u) -ne 0 ]]; then
  echo "setup: missing Debian packages; run this once, then again ./setup.sh:" >&2
  echo "  sudo apt-get update && sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"

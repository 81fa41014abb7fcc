#!/usr/bin/env bash
# Installs the Debian packages PartSLAM needs, only those that are missing. Idempotent.
set -euo pipefail
PACKAGES=(
  g++ make cmake pkg-config
  libeigen3-dev        # 2D geometry
  libceres-dev         # pose-graph optimisation (partslam slam)
  librosbag-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev libconsole-bridge-dev  # ROS 1 bags (io/logs)
  libyaml-cpp-dev      # map_server map.yaml (io/formats/map_server.h)
  libopenmpi-dev openmpi-bin  # mpirun -n P partslam eval (apps/mpi_split.h)
  libcli11-dev         # command-line parsing
  libsqlite3-dev       # map database
  zlib1g-dev           # gzip CARMEN logs
  libzstd-dev liblz4-dev  # ROS 2 bags: MCAP chunks (io/logs/mcap_file.h)
  libcairo2-dev        # PNG rendering (Fig. D, Fig. E)
  nlohmann-json3-dev   # --json output
  libgtest-dev libgmock-dev  # tests
  python3              # scripts/results_table.py (make results)
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module (python/) and its tests
  libbenchmark-dev     # benchmarks
  # make fuzz: clang 14 with libFuzzer and its sanitizer runtimes (libclang_rt.fuzzer-x86_64.a and
  # fuzzer/FuzzedDataProvider.h are in libclang-rt-14-dev, which clang only recommends; Debian's libfuzzer-14-dev
  # is the standalone library, not needed), and LLVM's OpenMP for clang builds
  clang libclang-rt-14-dev libomp-dev
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# make test only: tests/ros2 writes ROS 2 bags with independent libraries from npm. Any node >= 18 with npm will do
# (a machine may carry its own, e.g. NodeSource's, which bundles npm); Debian's otherwise.
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  missing+=(nodejs npm)
fi
[ ${#missing[@]} -eq 0 ] && exit 0
echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"

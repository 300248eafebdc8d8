#!/usr/bin/env bash
# Installs the Debian packages contact2d needs, only those that are missing.
# Idempotent and silent when everything is already there.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libeigen3-dev libsuitesparse-dev coinor-libipopt-dev libsundials-dev libceres-dev
  libgmsh-dev libtomlplusplus-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev libopenblas0-pthread gnuplot-nox
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  parallel  # GNU parallel: runs a study's jobs.txt (README; tests/app/job_list_test.cpp)
  chromium chromium-driver python3-selenium  # opens the studies' HTML pages (tests/browser)
  slurmctld slurmd slurm-client munge  # a one-node Slurm runs slurm.sh (tests/ecosystem/slurm_array_study.py)
  openssh-server openssh-client  # GNU parallel over ssh runs jobs.txt (tests/ecosystem/ssh_parallel_study.py)
  python3-vtk9 python3-gmsh  # VTK's and gmsh's own readers on the outputs (Ecosystem.VtkReadsOutputs, Ecosystem.GmshReadsMsh)
  python3-nbclient python3-nbformat python3-ipykernel  # runs examples/notebooks (Ecosystem.NotebookCompareMethods)
)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]} == 0)); then
  exit 0
fi
echo "bootstrap: installing ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get -o DPkg::Lock::Timeout=900 install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "bootstrap: done" >&2

#!/usr/bin/env bash
# Installs settle's build and run dependencies from Debian's package archive, and the packages
# given as arguments.
# Idempotent: packages already present are skipped, and apt-get is not touched at all
# when nothing is missing. Nothing is vendored or downloaded from elsewhere.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libtomlplusplus-dev   # case files (toml++)
  libcli11-dev          # command line (CLI11)
  libfmt-dev            # formatting
  nlohmann-json3-dev    # JSON output (summary.json, shape, bench) and reference data in tests
  libeigen3-dev         # small linear algebra (attitude, inertia)
  libgtest-dev libgmock-dev googletest   # tests
  libbenchmark-dev      # micro-benchmarks
  libopenmpi-dev openmpi-bin             # one run across many processes (docs/parallel.md)
  zlib1g-dev            # compressed VTK output
  python3-matplotlib python3-numpy       # `settle plot`
  python3-pandas python3-pytest          # the settle Python package (python/settle/) and its tests
)
# `--clang`: the sanitizer build's compiler (CMakePresets.json, debug), libFuzzer and clang's OpenMP
# runtime, for the sanitizer and fuzz stages only. Other arguments are extra packages.
for arg in "$@"; do
  if [[ $arg == --clang ]]; then packages+=(clang-14 libclang-rt-14-dev libomp-14-dev); else packages+=("$arg"); fi
done

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  exit 0
fi

echo "install-deps: installing ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null

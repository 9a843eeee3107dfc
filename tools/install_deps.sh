#!/usr/bin/env bash
# Installs the Debian packages omnidso builds against. Idempotent and silent when
# everything is already present; uses sudo only when not run as root.
set -euo pipefail

packages=(
  build-essential cmake make pkg-config ccache
  libeigen3-dev libceres-dev
  libopencv-dev libopencv-contrib-dev
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
)
# `install_deps.sh slurm`: instead, what `make test-slurm` needs — a local Slurm cluster with
# accounting (sacct) and GNU parallel, for `omnidso ablate --executor slurm|parallel`.
if [ "${1:-}" = slurm ]; then
  packages=(slurm-wlm slurmdbd munge mariadb-server parallel)
fi
# `make fuzz` only: libFuzzer comes with clang's runtime libraries.
if [ "${1:-}" = "--fuzz" ]; then
  packages+=(clang libclang-rt-dev)
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install_deps: installing ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_deps: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null

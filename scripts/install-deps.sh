#!/usr/bin/env bash
# Installs Pavilion's build and test dependencies from Debian 12 packages.
# Used by the README's quick start (make demo / make test) and by .ci/run.
# `--test` adds what only the tests need (headless Chromium for the report's
# browser test). Skips the apt run entirely when every package is already installed.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git clang-format ccache python3
  libbullet-dev libbullet-extras-dev libeigen3-dev
  libosmesa6-dev libompl-dev
  libboost-serialization-dev libboost-filesystem-dev libboost-system-dev
  liburdfdom-dev libassimp-dev
  libyaml-cpp-dev nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev libpng-dev zlib1g-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libjs-chart.js
)
if [ "${1:-}" = "--test" ]; then
  PACKAGES+=(chromium)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
start=$(date +%s)
APT=(-o DPkg::Lock::Timeout=900 -y -q)
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get "${APT[@]}" update
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get "${APT[@]}" install --no-install-recommends "${missing[@]}"
echo "install-deps: done in $(( $(date +%s) - start )) s"

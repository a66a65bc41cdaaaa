#!/usr/bin/env bash
# Installs the Debian packages skyfit needs (if missing) and builds it into
# build/. Used by both README commands. (For tests: chromium renders
# report.html in tests/cli_report.sh, glslang-tools and the EGL/GL packages
# check and run the emitted GLSL, clang builds tests/cli_fuzz_short.sh's
# fuzzers.)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config libnlopt-dev libceres-dev libopenexr-dev libcjson-dev clang libclang-rt-14-dev libomp-dev libpng-dev chromium glslang-tools libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "skyfit: installing ${missing[*]}" >&2
  if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; else SUDO=; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"

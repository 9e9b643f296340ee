#!/usr/bin/env bash
# Installs farfield's build and test dependencies from Debian's packages.
# Idempotent: installs only what is missing; does nothing when all is present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ninja-build
  libassimp-dev assimp-utils assimp-testmodels libstb-dev libmeshoptimizer-dev
  libcli11-dev libglm-dev libxxhash-dev nlohmann-json3-dev libpng-dev
  libsqlite3-dev libzstd-dev libturbojpeg0-dev
  libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev libimgui-dev
  python3-matplotlib xvfb xauth
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-14 libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"

#!/usr/bin/env bash
# Installs farfield's build and test dependencies: Debian's packages (Chromium for the web
# viewer's test), then the npm packages of web/ (the glTF validator, three.js,
# 3d-tiles-renderer, playwright-core), pinned by web/package-lock.json.
# Idempotent: installs only what is missing; does nothing when all is present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ninja-build
  libassimp-dev assimp-utils assimp-testmodels libstb-dev libmeshoptimizer-dev
  libcli11-dev libglm-dev libxxhash-dev nlohmann-json3-dev libpng-dev
  libsqlite3-dev libzstd-dev libturbojpeg0-dev libmimalloc-dev
  libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev libimgui-dev
  python3-matplotlib xvfb xauth
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-14 libclang-rt-14-dev
  libopenmpi-dev openmpi-bin
  chromium
)

missing=()
# Node.js and npm from Debian unless the machine has them already (from elsewhere).
if ! command -v npm > /dev/null; then missing+=(nodejs npm); fi
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# web/: installed again only when the lock file changed since the last install.
web="$(dirname "$0")/../web"
if [ ! -f "$web/node_modules/.package-lock.json" ] ||
   [ "$web/package-lock.json" -nt "$web/node_modules/.package-lock.json" ]; then
  echo "install-deps: npm ci in web/"
  if ! (cd "$web" && npm ci --no-audit --no-fund --loglevel=error); then
    echo "install-deps: npm ci in web/ failed; the tests that validate glTF files will skip" >&2
  fi
fi

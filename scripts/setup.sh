#!/usr/bin/env bash
# Installs whatever the build and the tests need that is missing (Debian 12 packages).
# Safe to run again: it only installs packages that are not installed yet.
set -euo pipefail

PACKAGES=(
  cmake ninja-build g++ pkg-config ccache
  libbullet-dev libeigen3-dev libfmt-dev doctest-dev nlohmann-json3-dev libcli11-dev
  libantlr4-runtime-dev antlr4 default-jre-headless uuid-dev
  graphviz gnuplot-nox
  libboost-dev chromium
  libyaml-cpp-dev openmpi-bin libopenmpi-dev
  neovim
  clang libclang-rt-14-dev
  libmodbus-dev mbpoll python3-pymodbus python3-serial-asyncio
  libzstd-dev libssl-dev openssl
)
# The viewer page's and the OPC UA server's packages come from npm (viewer/, opcua/: each
# with its package-lock.json): Node.js and npm from Debian when the machine has none.
command -v npm >/dev/null || PACKAGES+=(nodejs npm)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# npm ci for the viewer page when its packages are missing or older than the lockfile.
viewer_packages() {
  local dir
  dir="$(dirname "$0")/../viewer"
  if [ -f "$dir/package-lock.json" ] && { [ ! -f "$dir/node_modules/.package-lock.json" ] ||
       [ "$dir/package-lock.json" -nt "$dir/node_modules/.package-lock.json" ]; }; then
    echo "setup: npm ci in viewer/"
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
  fi
  # The OPC UA link's server (opcua/: node-opcua, pinned in its lockfile), and the server's
  # certificate for Basic256Sha256 (opcua/pki, node-opcua's PKI layout), made once.
  dir="$(dirname "$0")/../opcua"
  if [ ! -f "$dir/node_modules/.package-lock.json" ] ||
     [ "$dir/package-lock.json" -nt "$dir/node_modules/.package-lock.json" ]; then
    echo "setup: npm ci in opcua/"
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
  fi
  if [ ! -s "$dir/pki/own/certs/certificate.pem" ]; then
    echo "setup: the OPC UA server's certificate (opcua/pki)"
    (cd "$dir" && node server.mjs --init-pki)
  fi
  # The same for the VS Code extension (editors/vscode: its client, the grammar test, vsce).
  dir="$(dirname "$0")/../editors/vscode"
  if [ ! -f "$dir/node_modules/.package-lock.json" ] ||
     [ "$dir/package-lock.json" -nt "$dir/node_modules/.package-lock.json" ]; then
    echo "setup: npm ci in editors/vscode/"
    (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
  fi
}

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages are installed"
  viewer_packages
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then SUDO="sudo"; else
    echo "setup: need root (or sudo) to install: ${missing[*]}" >&2
    exit 1
  fi
fi
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
viewer_packages

#!/usr/bin/env bash
# Installs the buf CLI (npm's @bufbuild/buf, which ships buf's own prebuilt binary in the
# package for this platform), whose `buf lint` and `buf build` the CTest test Proto.BufLint runs
# on proto/ (buf.yaml at the repository root), into a folder of its own at $BUF_PREFIX (default
# /opt/vastray/buf; the binary is $BUF_PREFIX/node_modules/.bin/buf). npm comes with the
# machine's Node.js when it has one; otherwise Debian's `npm` package is installed.
# Idempotent: when the wanted version is installed it does nothing and needs no network.
# Uses sudo only when not root. scripts/install-deps.sh calls it.
set -euo pipefail

BUF_VERSION=${BUF_VERSION:-1.75.0}
BUF_PREFIX=${BUF_PREFIX:-/opt/vastray/buf}  # tests/CMakeLists.txt looks here
BUF_BIN="$BUF_PREFIX/node_modules/.bin/buf"

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi

installed=""
if [ -x "$BUF_BIN" ]; then installed=$("$BUF_BIN" --version 2> /dev/null || true); fi
if [ "$installed" = "$BUF_VERSION" ]; then
  echo "install-buf: buf $BUF_VERSION present in $BUF_PREFIX"
  exit 0
fi
if ! command -v npm > /dev/null; then
  # Not in install-deps.sh's package list: a machine whose Node.js comes from elsewhere (with
  # its own npm) would have Debian's npm conflict with it.
  echo "install-buf: installing Debian's npm"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends npm
fi
echo "install-buf: installing @bufbuild/buf $BUF_VERSION${installed:+ (replacing $installed)} into $BUF_PREFIX"
# Removed first: a folder of its own, holding nothing but this package and its binary.
$sudo rm -rf "$BUF_PREFIX"
$sudo mkdir -p "$BUF_PREFIX"
$sudo npm install --prefix "$BUF_PREFIX" --no-save --no-audit --no-fund --loglevel=error \
  "@bufbuild/buf@$BUF_VERSION"
echo "install-buf: installed $BUF_BIN ($("$BUF_BIN" --version))"

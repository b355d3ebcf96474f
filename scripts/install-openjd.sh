#!/usr/bin/env bash
# Installs openjd-cli (PyPI; Open Job Description's `openjd check` and `openjd run`), which the
# CTest test openjd_template runs on deploy/openjd/vastray-render.yaml, into a virtual
# environment of its own at $OPENJD_VENV (default /opt/vastray/openjd-venv).
# Idempotent: when the wanted version is installed it does nothing and needs no network.
# Uses sudo only when not root. scripts/install-deps.sh calls it.
set -euo pipefail

OPENJD_CLI_VERSION=${OPENJD_CLI_VERSION:-0.8.0}
# The libraries openjd-cli 0.8.0 resolved to when the template test was written: the runtime's
# reading of the actions' output (openjd-sessions) and the template schema (openjd-model).
OPENJD_SESSIONS_VERSION=${OPENJD_SESSIONS_VERSION:-0.13.0}
OPENJD_MODEL_VERSION=${OPENJD_MODEL_VERSION:-0.13.0}
OPENJD_VENV=${OPENJD_VENV:-/opt/vastray/openjd-venv}  # tests/CMakeLists.txt looks here

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi

installed=""
if [ -x "$OPENJD_VENV/bin/python" ]; then
  installed=$("$OPENJD_VENV/bin/python" -c \
    'import importlib.metadata as m; print(m.version("openjd-cli"))' 2> /dev/null || true)
fi
if [ "$installed" = "$OPENJD_CLI_VERSION" ] && [ -x "$OPENJD_VENV/bin/openjd" ]; then
  echo "install-openjd: openjd-cli $OPENJD_CLI_VERSION present in $OPENJD_VENV"
  exit 0
fi
echo "install-openjd: installing openjd-cli $OPENJD_CLI_VERSION into $OPENJD_VENV"
# Debian's python3 (not whichever python3 comes first on PATH), for a venv that outlives shells.
$sudo mkdir -p "$(dirname "$OPENJD_VENV")"
# Removed first, not `venv --clear`: an install interrupted half-way (pip still writing
# __pycache__) made --clear fail with "Directory not empty".
$sudo rm -rf "$OPENJD_VENV"
$sudo /usr/bin/python3 -m venv "$OPENJD_VENV"
$sudo "$OPENJD_VENV/bin/pip" install -q --disable-pip-version-check "openjd-cli==$OPENJD_CLI_VERSION" \
  "openjd-sessions==$OPENJD_SESSIONS_VERSION" "openjd-model==$OPENJD_MODEL_VERSION"

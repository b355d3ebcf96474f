#!/usr/bin/env bash
# Load-test clients for bench/load/run.sh (`make bench-load`); not needed by `make test`.
#   wrk            Debian package (HTTP load)
#   ghz v0.93.0    Go module proxy (gRPC load)
# grpcurl (one-off gRPC calls) is not installed here: scripts/install-deps.sh builds it (the
# version the end-to-end tests use) with Debian's Go; this script only reports it.
# Idempotent: a tool already on PATH at the wanted version is left alone.
# Needs Go (GO=/usr/local/go/bin/go by default) and root for apt-get / GOBIN=/usr/local/bin.
set -euo pipefail
GO=${GO:-$(command -v go || echo /usr/local/go/bin/go)}
GOBIN_DIR=${GOBIN_DIR:-/usr/local/bin}
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi

if ! command -v wrk > /dev/null; then
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends wrk
fi

go_tool() {  # name module version
  local name=$1 module=$2 version=$3
  if [ -x "$GOBIN_DIR/$name" ] && "$GO" version -m "$GOBIN_DIR/$name" 2> /dev/null | grep -q "mod.*$version"; then
    echo "$name $version already installed"
    return
  fi
  if [ ! -x "$GO" ]; then
    echo "install-bench-tools: Go not found (set GO=/path/to/go)" >&2
    exit 1
  fi
  echo "installing $name $version (go install, Go module proxy)"
  $SUDO env GOBIN="$GOBIN_DIR" GOFLAGS=-mod=mod "$GO" install "$module@$version"
}

go_tool ghz github.com/bojand/ghz/cmd/ghz v0.93.0
if [ ! -x "$GOBIN_DIR/grpcurl" ]; then
  echo "install-bench-tools: no $GOBIN_DIR/grpcurl: run scripts/install-deps.sh (it installs grpcurl)" >&2
fi
wrk -v 2>&1 | head -1 || true
# go-installed binaries report "dev" themselves; the module version is in their build info.
for tool in ghz grpcurl; do
  if [ -x "$GOBIN_DIR/$tool" ]; then
    echo "$tool $("$GO" version -m "$GOBIN_DIR/$tool" | awk '$1 == "mod" {print $3; exit}')"
  fi
done

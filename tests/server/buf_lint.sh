#!/usr/bin/env bash
# CTest Proto.BufLint: the service's protos (proto/vastray/v1, the module buf.yaml names) pass
# `buf lint` with buf's default rules and build with `buf build`. Any finding fails; so does a
# missing buf (scripts/install-deps.sh installs it, through scripts/install-buf.sh).
# Usage: buf_lint.sh BUF REPOSITORY_ROOT
set -uo pipefail
buf=$1 root=$2
if [ ! -x "$buf" ]; then
  echo "Proto.BufLint: no buf at $buf: run scripts/install-deps.sh (it installs buf with scripts/install-buf.sh)" >&2
  exit 1
fi
cd "$root" || exit 1
echo "buf $("$buf" --version) on $("$buf" ls-files | tr '\n' ' ')"
findings=$("$buf" lint --error-format text 2>&1)
status=$?
if [ $status -ne 0 ] || [ -n "$findings" ]; then
  echo "$findings"
  echo "Proto.BufLint: buf lint found $(grep -c . <<< "$findings") problems (exit $status)" >&2
  exit 1
fi
if ! "$buf" build --error-format text; then
  echo "Proto.BufLint: buf build failed" >&2
  exit 1
fi
echo "buf lint: no findings; buf build: ok"

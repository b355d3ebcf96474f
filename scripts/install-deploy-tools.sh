#!/usr/bin/env bash
# Installs the tools that validate the Kubernetes chart (deploy/helm/vastray) offline, for the
# CTest tests labelled `deploy` (tests/deploy/), into $DEPLOY_TOOLS (default
# /opt/vastray/deploy-tools):
#   bin/helm          helm.sh/helm/v3, built from the Go module proxy (`helm lint`, `helm template`)
#   bin/kubeconform   github.com/yannh/kubeconform, the same way (schema validation, -strict)
#   venv/             PyPI kubernetes-validate: a second validator, and the Kubernetes JSON schemas
#                     it bundles (kubernetes_validate/kubernetes-json-schema/v1.NN.0-local-strict)
#   schemas/vX.Y.Z-local-strict/   those schemas for $KUBERNETES_SCHEMA_VERSIONS, rewritten for
#                     kubeconform: its default schema location (a GitHub repository) is not
#                     reachable here, and the bundled files name each other by https://kubernetes.io
#                     URLs ($id, $ref "/api/_definitions.json#..."), which kubeconform would fetch;
#                     without $id their $refs resolve to the file beside them.
# Both Go tools need a newer Go than Debian 12's 1.19: GO defaults to /usr/local/go/bin/go (the
# machine image's Go 1.26), else the first `go` on PATH.
# Idempotent: when the wanted versions are installed it does nothing and needs no network.
# Uses sudo only when not root. tests/CMakeLists.txt runs it as the fixture of the deploy tests.
set -euo pipefail

HELM_MODULE=helm.sh/helm/v3
HELM_VERSION=${HELM_VERSION:-v3.22.0}
KUBECONFORM_MODULE=github.com/yannh/kubeconform
KUBECONFORM_VERSION=${KUBECONFORM_VERSION:-v0.8.0}
KUBERNETES_VALIDATE_VERSION=${KUBERNETES_VALIDATE_VERSION:-1.37.0}
# The oldest Kubernetes the chart supports (Chart.yaml kubeVersion) and the newest bundled.
KUBERNETES_SCHEMA_VERSIONS=${KUBERNETES_SCHEMA_VERSIONS:-"1.29.0 1.37.0"}
DEPLOY_TOOLS=${DEPLOY_TOOLS:-/opt/vastray/deploy-tools}  # tests/CMakeLists.txt looks here
if [ -z "${GO:-}" ]; then
  if [ -x /usr/local/go/bin/go ]; then GO=/usr/local/go/bin/go; else GO=$(command -v go || true); fi
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi

# The module version a go-installed binary was built from ("" when absent).
built_version() {  # binary module
  [ -x "$1" ] || return 0
  "$GO" version -m "$1" 2> /dev/null | awk -v m="$2" '$1 == "mod" && $2 == m {print $3; exit}' || true
}

go_tool() {  # name module package version
  local name=$1 module=$2 package=$3 version=$4 have work
  if [ -z "$GO" ] || [ ! -x "$GO" ]; then
    echo "install-deploy-tools: no Go found for $name (set GO=/path/to/go, Go >= 1.24)" >&2
    exit 1
  fi
  have=$(built_version "$DEPLOY_TOOLS/bin/$name" "$module")
  if [ "$have" = "$version" ]; then
    echo "install-deploy-tools: $name $version present"
    return
  fi
  echo "install-deploy-tools: building $name $version with $("$GO" version)"
  # A throw-away GOPATH, module and build cache: nothing outside it but the binary is kept.
  work=$(mktemp -d)
  env GOPATH="$work/gopath" GOMODCACHE="$work/gopath/pkg/mod" GOCACHE="$work/cache" GOBIN="$work/bin" \
    GOFLAGS="-modcacherw -buildvcs=false" CGO_ENABLED=0 GOTOOLCHAIN=local \
    "$GO" install -ldflags="-s -w" "$package@$version"
  $sudo mkdir -p "$DEPLOY_TOOLS/bin"
  $sudo install -m 0755 "$work/bin/$name" "$DEPLOY_TOOLS/bin/$name"
  rm -rf "$work"
}

go_tool helm "$HELM_MODULE" "$HELM_MODULE/cmd/helm" "$HELM_VERSION"
go_tool kubeconform "$KUBECONFORM_MODULE" "$KUBECONFORM_MODULE/cmd/kubeconform" "$KUBECONFORM_VERSION"

venv=$DEPLOY_TOOLS/venv
installed=""
if [ -x "$venv/bin/python" ]; then
  installed=$("$venv/bin/python" -c \
    'import importlib.metadata as m; print(m.version("kubernetes-validate"))' 2> /dev/null || true)
fi
if [ "$installed" = "$KUBERNETES_VALIDATE_VERSION" ]; then
  echo "install-deploy-tools: kubernetes-validate $KUBERNETES_VALIDATE_VERSION present in $venv"
else
  echo "install-deploy-tools: installing kubernetes-validate $KUBERNETES_VALIDATE_VERSION into $venv"
  # Removed first, not `venv --clear` (see scripts/install-openjd.sh); Debian's python3. The
  # rewritten schemas go with it: they come from this version.
  $sudo rm -rf "$venv" "$DEPLOY_TOOLS/schemas"
  $sudo mkdir -p "$DEPLOY_TOOLS"
  $sudo /usr/bin/python3 -m venv "$venv"
  $sudo "$venv/bin/pip" install -q --disable-pip-version-check "kubernetes-validate==$KUBERNETES_VALIDATE_VERSION"
fi

for version in $KUBERNETES_SCHEMA_VERSIONS; do
  out=$DEPLOY_TOOLS/schemas/v$version-local-strict
  if [ -f "$out/_definitions.json" ]; then
    echo "install-deploy-tools: Kubernetes $version schemas present"
    continue
  fi
  echo "install-deploy-tools: Kubernetes $version schemas for kubeconform into $out"
  $sudo "$venv/bin/python" "$(dirname "$0")/../tests/deploy/local_schemas.py" "$version" "$out"
done

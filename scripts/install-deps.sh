#!/usr/bin/env bash
# Installs everything vastray needs to build, test and run on Debian 12: Debian packages with
# apt-get, and grpcurl (a Go tool the render service's end-to-end tests drive) built from the
# Go module proxy with Debian's own Go (golang-go, Go 1.19) into /usr/local/bin. cpp-httplib
# is vendored (third_party/); clang-14 and libFuzzer serve scripts/fuzz.sh only. And
# openapi-spec-validator (PyPI), which tests/server/OpenApiTest.cpp runs on /openapi.json, in a
# virtual environment of its own at $OPENAPI_VENV (default /opt/vastray/openapi-venv).
# Idempotent: when every package is installed, /usr/local/bin/grpcurl and the validator are the
# wanted versions it does nothing (and needs no network). Uses sudo only when not root.
# node-typescript (tsc) compiles the service's web page at build time (server/web/); chromium,
# chromium-driver, python3-selenium and python3-pil (screenshots) run its browser test
# (tests/server/web_page_test.py). libpq-dev builds the PostgreSQL job store (`serve --database`);
# postgresql (15, its initdb/pg_ctl/psql in /usr/lib/postgresql/15/bin) runs its tests, each of
# which starts a throw-away cluster of its own (tests/server/PostgresCluster.h); the cluster
# that Debian's package sets up is not used. scripts/install-openjd.sh (openjd-cli, PyPI) and
# scripts/install-buf.sh (the buf CLI, npm's @bufbuild/buf, which the test Proto.BufLint runs)
# install into folders of their own under /opt/vastray, idempotently too.
set -euo pipefail

# grpcurl v1.9.1 is the newest release whose go.mod (and whose dependencies' go.mod: grpc
# v1.61.0, protobuf v1.33) ask for at most Go 1.19, the Go of Debian 12; v1.9.2 and later need
# Go 1.21. Override with GRPCURL_VERSION=... only together with a newer GO=/path/to/go.
GRPCURL_MODULE=github.com/fullstorydev/grpcurl
GRPCURL_VERSION=${GRPCURL_VERSION:-v1.9.1}
GO=${GO:-/usr/lib/go/bin/go}  # Debian's golang-go; not whichever `go` comes first on PATH
GRPCURL_BIN=/usr/local/bin/grpcurl
OPENAPI_VALIDATOR_VERSION=${OPENAPI_VALIDATOR_VERSION:-0.9.0}
OPENAPI_VENV=${OPENAPI_VENV:-/opt/vastray/openapi-venv}  # tests/server/OpenApiTest.cpp looks here

packages=(
  ca-certificates build-essential cmake ninja-build pkg-config git
  libembree-dev libopenvdb-dev libnanovdb-dev libboost-iostreams-dev libdraco-dev
  libtinygltf-dev nlohmann-json3-dev libopenimageio-dev openimageio-tools libglm-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers glslang-dev glslang-tools
  libshaderc-dev glslc spirv-tools
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libssl-dev
  libspdlog-dev libtbb-dev libmeshoptimizer-dev libsqlite3-dev libxxhash-dev libzstd-dev libzip-dev libassimp-dev
  libpq-dev postgresql
  assimp-testmodels python3 python3-matplotlib python3-venv python3-pip time
  curl openssl golang-go
  node-typescript chromium chromium-driver python3-selenium python3-pil
  clang-14 libfuzzer-14-dev libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing+=("$p")
done
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
else
  echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi


installed_validator=""
if [ -x "$OPENAPI_VENV/bin/python" ]; then
  installed_validator=$("$OPENAPI_VENV/bin/python" -c \
    'import importlib.metadata as m; print(m.version("openapi-spec-validator"))' 2> /dev/null || true)
fi
if [ "$installed_validator" = "$OPENAPI_VALIDATOR_VERSION" ]; then
  echo "install-deps: openapi-spec-validator $OPENAPI_VALIDATOR_VERSION present in $OPENAPI_VENV"
else
  echo "install-deps: installing openapi-spec-validator $OPENAPI_VALIDATOR_VERSION into $OPENAPI_VENV"
  # Debian's python3 (not whichever python3 comes first on PATH), for a venv that outlives shells.
  $sudo mkdir -p "$(dirname "$OPENAPI_VENV")"
  # Removed first, not `venv --clear`: an install interrupted half-way (pip still writing
  # __pycache__) made --clear fail with "Directory not empty".
  $sudo rm -rf "$OPENAPI_VENV"
  $sudo /usr/bin/python3 -m venv "$OPENAPI_VENV"
  $sudo "$OPENAPI_VENV/bin/pip" install -q --disable-pip-version-check \
    "openapi-spec-validator==$OPENAPI_VALIDATOR_VERSION"
fi

bash "$(dirname "$0")/install-openjd.sh"
bash "$(dirname "$0")/install-buf.sh"
# The module version grpcurl was built from (go-installed binaries call themselves "dev build").
installed_grpcurl=""
if [ -x "$GRPCURL_BIN" ]; then
  installed_grpcurl=$("$GO" version -m "$GRPCURL_BIN" 2> /dev/null |
    awk -v m="$GRPCURL_MODULE" '$1 == "mod" && $2 == m {print $3; exit}' || true)
fi
if [ "$installed_grpcurl" = "$GRPCURL_VERSION" ]; then
  echo "install-deps: grpcurl $GRPCURL_VERSION present"
  exit 0
fi
echo "install-deps: building grpcurl $GRPCURL_VERSION${installed_grpcurl:+ (replacing $installed_grpcurl)}" \
  "from the Go module proxy with $("$GO" version)"
# A throw-away GOPATH, module and build cache: nothing outside it but the binary is kept.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
env GOPATH="$work/gopath" GOMODCACHE="$work/gopath/pkg/mod" GOCACHE="$work/cache" GOBIN="$work/bin" \
  GOFLAGS=-modcacherw GOTOOLCHAIN=local \
  "$GO" install "$GRPCURL_MODULE/cmd/grpcurl@$GRPCURL_VERSION"
$sudo install -m 0755 "$work/bin/grpcurl" "$GRPCURL_BIN"
echo "install-deps: installed $GRPCURL_BIN ($GRPCURL_VERSION)"

#!/usr/bin/env bash
# Installs everything vastray needs to build, test and run on Debian 12, with apt-get only.
# Idempotent: when every package is already installed it does nothing (and needs no network).
# Uses sudo only when not root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libembree-dev libopenvdb-dev libnanovdb-dev libboost-iostreams-dev libdraco-dev
  libtinygltf-dev nlohmann-json3-dev libopenimageio-dev openimageio-tools libglm-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-tools glslang-dev glslang-tools
  libshaderc-dev glslc spirv-tools
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libgtest-dev libgmock-dev libbenchmark-dev libcpp-httplib-dev libcli11-dev
  libspdlog-dev libtbb-dev libmeshoptimizer-dev libsqlite3-dev libxxhash-dev
  assimp-testmodels python3 python3-matplotlib time
  curl openssl
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
$sudo apt-get update -q
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"

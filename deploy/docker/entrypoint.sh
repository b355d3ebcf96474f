#!/bin/sh
# The image's entry point: `vastray ARGS...`, with NVIDIA's Vulkan driver made visible to the
# Vulkan loader when NVIDIA's container runtime mounted the driver's libraries but not its ICD
# file. Recent NVIDIA Container Toolkits mount the host's /etc/vulkan/icd.d/nvidia_icd.json
# with the `graphics` capability, older ones do not; where it is mounted ours is left out, so
# that the loader does not list the GPU twice. Without an NVIDIA driver the loader finds Mesa's
# lavapipe (a CPU Vulkan device) only.
set -eu
if [ ! -e /etc/vulkan/icd.d/nvidia_icd.json ] && [ ! -e /usr/share/vulkan/icd.d/nvidia_icd.json ] &&
  ldconfig -p | grep -q 'libGLX_nvidia\.so\.0'; then
  VK_ADD_DRIVER_FILES=/opt/vastray/vulkan/nvidia_icd.json${VK_ADD_DRIVER_FILES:+:$VK_ADD_DRIVER_FILES}
  export VK_ADD_DRIVER_FILES
fi
exec vastray "$@"

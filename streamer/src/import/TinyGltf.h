#pragma once
// The one place that configures tinygltf: every file that includes it must see the same
// macros. Draco is enabled (Debian's prebuilt libtinygltf lacks it); images are never
// decoded by tinygltf (GltfLoader.cpp keeps embedded ones encoded) and external images are never
// opened by it (GltfTextures.cpp reads those a material uses, inside the model's folder).
#define TINYGLTF_ENABLE_DRACO
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

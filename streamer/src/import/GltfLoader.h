#pragma once
// Loads a .gltf/.glb into a tinygltf::Model after the checks tinygltf does not do:
// GLB header, required extensions, Draco extension references, and a file-system
// sandbox that keeps every external URI inside the model's folder.
#include <string>

#include "import/TinyGltf.h"
#include "vastray/core/Result.h"

namespace vastray::import {

Result<tinygltf::Model> loadGltfModel(const std::string& path, bool binary);

}  // namespace vastray::import

#pragma once
// Loads a .gltf/.glb into a tinygltf::Model after the checks tinygltf does not do:
// GLB header, required extensions, Draco extension references, and a file-system
// sandbox that keeps every external URI inside the model's folder.
#include <string>

#include "import/TinyGltf.h"
#include "vastray/core/Result.h"

namespace vastray::import {

// `version1` is set when the file is glTF 1.0 (GLB version 1, or asset.version "1.x"): the
// error then says so, and the caller may hand the file to assimp, which reads 1.0.
Result<tinygltf::Model> loadGltfModel(const std::string& path, bool binary, bool* version1 = nullptr);

}  // namespace vastray::import

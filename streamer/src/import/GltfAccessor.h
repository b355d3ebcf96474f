#pragma once
// Bounds-checked reads of glTF accessors: tinygltf parses the JSON but does not prove
// that an accessor fits inside its bufferView and buffer. Messages name the accessor.
#include <cstdint>
#include <vector>

#include "import/TinyGltf.h"
#include "vastray/core/Result.h"

namespace vastray::import {

// VEC3 positions as doubles (float, or normalized/integer components for quantized files).
Status readVec3Accessor(const tinygltf::Model& model, int accessor, std::vector<double>& xyz);

// SCALAR unsigned 8/16/32-bit indices.
Status readIndexAccessor(const tinygltf::Model& model, int accessor, std::vector<uint32_t>& indices);

}  // namespace vastray::import

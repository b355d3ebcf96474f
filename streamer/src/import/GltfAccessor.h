#pragma once
// Bounds-checked reads of glTF accessors: tinygltf parses the JSON but does not prove
// that an accessor fits inside its bufferView and buffer. Messages name the accessor.
#include <cstdint>
#include <string>
#include <vector>

#include "import/TinyGltf.h"
#include "vastray/core/Result.h"

namespace vastray::import {

// VEC3 values as doubles (float, or normalized/integer components for quantized files);
// `what` names the attribute in messages.
Status readVec3Accessor(const tinygltf::Model& model, int accessor, std::vector<double>& xyz,
                        const char* what = "POSITION");

// COLOR_0: VEC3 or VEC4 (float, normalized unsigned byte or short) as RGB doubles in [0, 1],
// three per element (alpha is dropped).
Status readColorAccessor(const tinygltf::Model& model, int accessor, std::vector<double>& rgb);

// TEXCOORD_n: VEC2 of floats or normalized unsigned bytes or shorts (spec 3.7.2.1), two per
// element; a value not finite or beyond +-kMaxAbsUv is an error naming the accessor and element.
Status readUvAccessor(const tinygltf::Model& model, int accessor, const std::string& what, std::vector<double>& uv);

// SCALAR unsigned 8/16/32-bit indices.
Status readIndexAccessor(const tinygltf::Model& model, int accessor, std::vector<uint32_t>& indices);

}  // namespace vastray::import

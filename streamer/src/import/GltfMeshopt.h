#pragma once
// EXT_meshopt_compression (glTF 2.0 vendor extension; what gltfpack -cc writes): bufferViews
// whose bytes are meshoptimizer's vertex/index codecs, optionally filtered (octahedral,
// quaternion, exponential). Before tinygltf parses the document, each such view is pointed
// at its compressed bytes and a fallback buffer without data gets an empty data: URI; after
// it, the views are decoded with meshoptimizer into buffers of their own, so that accessors
// read them as any other view.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "import/TinyGltf.h"
#include "vastray/core/Result.h"

namespace vastray::import {

struct MeshoptView {
    size_t view = 0;
    uint64_t count = 0;
    uint64_t stride = 0;  // bytes per element of the decoded data
    std::string mode;     // ATTRIBUTES | TRIANGLES | INDICES
    std::string filter;   // NONE | OCTAHEDRAL | QUATERNION | EXPONENTIAL
};

// Decoded bytes may be at most this many times the compressed ones (plus a small constant):
// the vertex codec's densest case is 64:1 (16 equal bytes in 2 header bits), so a file
// cannot ask for gigabytes from a few bytes.
constexpr uint64_t kMaxMeshoptExpansion = 128;

// Rewrites `doc` (its types already checked) and lists the views to decode. Errors name
// the bufferView and the field.
Status prepareMeshopt(nlohmann::json& doc, std::vector<MeshoptView>& views);

Status decodeMeshopt(tinygltf::Model& model, const std::vector<MeshoptView>& views);

}  // namespace vastray::import

#pragma once
// tinygltf (2.7) decodes KHR_draco_mesh_compression while parsing and dereferences the
// attribute it looks up by id without checking that it exists. This decodes each Draco
// bitstream first and proves every id the primitive names is present.
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "vastray/core/Result.h"

namespace vastray::import {

// `doc` has passed checkDocument (indices and byte ranges are valid); `glbBin` is the GLB
// BIN chunk (empty for .gltf); `folder` holds external buffers.
Status checkDracoAttributes(const nlohmann::json& doc, std::string_view glbBin, const std::string& folder);

}  // namespace vastray::import

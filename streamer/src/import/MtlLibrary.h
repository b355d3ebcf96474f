#pragma once
// The subset of Wavefront .mtl that vastray renders: Kd (base colour) and Ke (emission).
#include <array>
#include <string>
#include <unordered_map>

#include "vastray/core/Result.h"

namespace vastray::import {

struct MtlEntry {
    std::array<float, 3> diffuse{0.8f, 0.8f, 0.8f};
    std::array<float, 3> emissive{0.0f, 0.0f, 0.0f};
};

using MtlLibrary = std::unordered_map<std::string, MtlEntry>;

// Adds the materials of `path` to `library`. d/Tr, maps and other statements are ignored.
Status parseMtlFile(const std::string& path, MtlLibrary& library);

}  // namespace vastray::import

#pragma once
// The subset of Wavefront .mtl that vastray renders: Kd (base colour), Ke (emission), and Ks and
// Ns (a specular layer: its weight the largest Ks component, its roughness from the Phong
// exponent, docs/RENDERING.md "Materials").
#include <array>
#include <string>
#include <unordered_map>

#include "vastray/core/Result.h"

namespace vastray::import {

struct MtlEntry {
    std::array<float, 3> diffuse{0.8f, 0.8f, 0.8f};
    std::array<float, 3> emissive{0.0f, 0.0f, 0.0f};
    std::array<float, 3> specular{0.0f, 0.0f, 0.0f};
    float exponent = 0.0f;  // Ns
    int illumination = 2;   // illum: 0 and 1 have no highlight (Ks unused)
};

using MtlLibrary = std::unordered_map<std::string, MtlEntry>;

// Adds the materials of `path` to `library`. d/Tr, maps and other statements are ignored.
Status parseMtlFile(const std::string& path, MtlLibrary& library);

}  // namespace vastray::import

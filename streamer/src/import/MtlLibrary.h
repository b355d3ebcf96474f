#pragma once
// The subset of Wavefront .mtl that vastray renders: Kd (base colour), Ke (emission), and Ks and
// Ns (a specular layer: its weight the largest Ks component, its roughness from the Phong
// exponent, docs/RENDERING.md "Materials").
#include <array>
#include <cstdint>
#include <map>
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

// What a library says and the renderer does not use, by kind ("texture maps", ...), for the OBJ
// importer's warnings (once per kind).
using MtlUnused = std::map<std::string, uint64_t>;

// Adds the materials of `path` to `library`. Texture maps, transparency (d below 1, Tr above
// 0) and the PBR extension's statements (Pr, Pm, ...) are counted in `unused`; other statements
// are ignored.
Status parseMtlFile(const std::string& path, MtlLibrary& library, MtlUnused& unused);

}  // namespace vastray::import

#pragma once
// The subset of Wavefront .mtl that vastray renders: Kd (base colour), Ke (emission), and Ks and
// Ns (a specular layer: its weight the largest Ks component, its roughness from the Phong
// exponent, docs/RENDERING.md "Materials"), and the maps that have a glTF slot: map_Kd (base
// colour), norm (a tangent-space normal map) and map_Ke (emissive), with their -s, -o and
// -clamp options, and map_d (a cut-out's mask, with its -imfchan channel).
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>

#include "vastray/core/MaterialTextures.h"
#include "vastray/core/Result.h"

namespace vastray::import {

// One map statement: "map_Kd -s 2 2 -clamp on my bricks.png". The MTL texture space has v up
// (OBJ's vt); -s and -o map it as u' = s_u u + o_u, v' = s_v v + o_v (w is ignored).
struct MtlMap {
    std::string file;  // the rest of the line after the options (may hold spaces); empty: no map
    uint64_t line = 0;
    std::array<float, 2> scale{1.0f, 1.0f};
    std::array<float, 2> offset{0.0f, 0.0f};
    bool clamp = false;  // -clamp on; repeat otherwise
    char channel = 0;    // -imfchan r, g, b, m, l or z; 0 without (read for map_d only)
};


struct MtlEntry {
    std::array<float, 3> diffuse{0.8f, 0.8f, 0.8f};
    std::array<float, 3> emissive{0.0f, 0.0f, 0.0f};
    std::array<float, 3> specular{0.0f, 0.0f, 0.0f};
    float exponent = 0.0f;  // Ns
    int illumination = 2;   // illum: 0 and 1 have no highlight (Ks unused)
    // d (or 1 - Tr), clamped to [0, 1]: below 1 the material blends (Material::alphaBlend).
    float opacity = 1.0f;
    std::array<MtlMap, kTextureSlotCount> maps{};  // by TextureSlot; MetallicRoughness and Occlusion stay empty
    // map_d: a cut-out's mask (docs/RENDERING.md, "Cut-outs"; its -imfchan picks the channel):
    // map_Kd's own image's alpha cuts as it is, another image is baked into map_Kd's alpha.
    MtlMap alphaMap;
    std::string library;  // the mtllib name that defined it: map files are relative to its folder
};

using MtlLibrary = std::unordered_map<std::string, MtlEntry>;

// What a library says and the renderer does not use, by kind ("alpha maps (map_d)", ...) with
// its count and consequence, for the OBJ importer's warnings (once per kind).
struct MtlUnused {
    std::map<std::string, std::pair<uint64_t, std::string>> kinds;
    uint64_t maps = 0;  // map statements of every kind, read or not: the OBJ's UVs are kept with one
    void add(const std::string& what, const std::string& consequence) {
        auto& kind = kinds[what];
        ++kind.first;
        kind.second = consequence;
    }
};

// Adds the materials of `path` (named `libraryName` in the OBJ's mtllib) to `library`. Maps
// without a glTF slot (map_Ka, map_Ks, bump: a height map, map_Pr and map_Pm: two images
// where glTF has one, ...), map options that change the look and are not read (-mm, -t, -cc on,
// ..., -imfchan on other maps than map_d), transparency (d below 1, Tr above 0) and the PBR extension's statements (Pr, Pm, ...)
// are counted in `unused`; other statements are ignored.
Status parseMtlFile(const std::string& path, const std::string& libraryName, MtlLibrary& library, MtlUnused& unused);

}  // namespace vastray::import

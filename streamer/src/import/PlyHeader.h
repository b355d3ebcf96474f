#pragma once
// PLY header: format, elements and their properties, with every element count checked
// against the bytes the body actually has (before anyone allocates for it).
#include <cstdint>
#include <string>
#include <vector>

#include "vastray/core/Result.h"

namespace vastray::import {

enum class PlyType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyFormat : uint8_t { Ascii, BinaryLittleEndian, BinaryBigEndian };

inline uint32_t plySize(PlyType t) {
    constexpr uint32_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[static_cast<int>(t)];
}
inline bool isFloatType(PlyType t) { return t == PlyType::Float32 || t == PlyType::Float64; }

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;  // item type for lists
    bool isList = false;
    PlyType countType = PlyType::UInt8;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;

    bool hasLists() const;
    uint64_t minRowBytes(PlyFormat format) const;  // lists counted as empty
};

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    size_t bodyOffset = 0;  // first byte after "end_header\n"
    // "comment TextureFile <image>" lines (MeshLab's, the PLY way to name a texture map): the
    // file's UVs are kept only with one (ImportReport::textureMaps).
    uint64_t textureFiles = 0;
};

// `name` prefixes every message ("bunny.ply: ...").
Result<PlyHeader> parsePlyHeader(const char* data, size_t size, const std::string& name);

}  // namespace vastray::import

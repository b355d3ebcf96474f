#pragma once
// Helpers for the importer tests: tiny files written into VASTRAY_TEST_TMP, and a small
// glTF builder that embeds its buffer as a base64 data: URI.
#include "TestTmp.h"
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "vastray/streamer/Import.h"

namespace vastray::test {

// Each coordinate of a within `tolerance` of b's, `what` naming the vector in a failure.
inline void expectNear(const Vec3f& a, const Vec3f& b, float tolerance, const std::string& what) {
    EXPECT_NEAR(a.x, b.x, tolerance) << what;
    EXPECT_NEAR(a.y, b.y, tolerance) << what;
    EXPECT_NEAR(a.z, b.z, tolerance) << what;
}

inline std::string tmpPath(const std::string& name) {
    const std::filesystem::path dir = vastray::test::testTmpDir("import");
    std::filesystem::create_directories(dir);
    return (dir / name).string();
}

inline std::string writeFile(const std::string& name, const std::string& bytes) {
    const std::string path = tmpPath(name);
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return path;
}

// A valid 1x1 RGBA PNG (one opaque-ish texel), for importers' texture maps and import's decoder.
inline std::string tinyPng() {
    static const unsigned char bytes[] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
        0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00, 0x00, 0x1f, 0x15, 0xc4, 0x89, 0x00, 0x00, 0x00,
        0x0d, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x64, 0x60, 0xf8, 0x5f, 0x0f, 0x00, 0x02, 0x87, 0x01, 0x80,
        0xeb, 0x47, 0xba, 0x92, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    return std::string(reinterpret_cast<const char*>(bytes), sizeof(bytes));
}

template <typename T>
void appendRaw(std::string& out, T value, bool bigEndian = false) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (bigEndian) std::reverse(raw, raw + sizeof(T));
    out.append(raw, sizeof(T));
}

inline std::string base64(const std::string& in) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
        uint32_t n = uint8_t(in[i]) << 16;
        if (i + 1 < in.size()) n |= uint8_t(in[i + 1]) << 8;
        if (i + 2 < in.size()) n |= uint8_t(in[i + 2]);
        out += table[(n >> 18) & 63];
        out += table[(n >> 12) & 63];
        out += i + 1 < in.size() ? table[(n >> 6) & 63] : '=';
        out += i + 2 < in.size() ? table[n & 63] : '=';
    }
    return out;
}

// One buffer, one bufferView per accessor. Callers add meshes/nodes/scenes as raw JSON.
class GltfBuilder {
public:
    int addPositions(const std::vector<float>& xyz) {
        std::string bytes;
        for (float f : xyz) appendRaw(bytes, f);
        return addAccessor(bytes, 5126, "VEC3", xyz.size() / 3);
    }
    template <typename T>
    int addIndices(const std::vector<T>& indices) {
        std::string bytes;
        for (T i : indices) appendRaw(bytes, i);
        const int type = sizeof(T) == 1 ? 5121 : sizeof(T) == 2 ? 5123 : 5125;
        return addAccessor(bytes, type, "SCALAR", indices.size());
    }
    int addAccessor(const std::string& bytes, int componentType, const char* type, size_t count) {
        while (bin_.size() % 4) bin_ += '\0';
        views_ += (views_.empty() ? "" : ",") + std::string("{\"buffer\":0,\"byteOffset\":") +
                  std::to_string(bin_.size()) + ",\"byteLength\":" + std::to_string(bytes.size()) + "}";
        bin_ += bytes;
        accessors_ += (accessors_.empty() ? "" : ",") + std::string("{\"bufferView\":") + std::to_string(viewCount_++) +
                      ",\"componentType\":" + std::to_string(componentType) + ",\"type\":\"" + type +
                      "\",\"count\":" + std::to_string(count) + "}";
        return accessorCount_++;
    }
    std::string json(const std::string& rest) const {
        return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(bin_.size()) +
               ",\"uri\":\"data:application/octet-stream;base64," + base64(bin_) + "\"}],\"bufferViews\":[" + views_ +
               "],\"accessors\":[" + accessors_ + "]," + rest + "}";
    }

private:
    std::string bin_, views_, accessors_;
    int viewCount_ = 0, accessorCount_ = 0;
};

inline std::string glb(std::string json, std::string bin) {
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string out = "glTF";
    const uint32_t length = uint32_t(12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size()));
    appendRaw(out, uint32_t(2));
    appendRaw(out, length);
    appendRaw(out, uint32_t(json.size()));
    appendRaw(out, uint32_t(0x4E4F534A));
    out += json;
    if (!bin.empty()) {
        appendRaw(out, uint32_t(bin.size()));
        appendRaw(out, uint32_t(0x004E4942));
        out += bin;
    }
    return out;
}

// Asserts failure and that the message names the file and contains `element`.
// Collada: the triangle (0,0,0), (1,0,0), (0,1,0) as a geometry library, then the start of a
// visual scene whose node "tri" places it; a test file puts its own libraries before it and its
// nodes, the scene's end and <scene> after it.
inline constexpr const char* kColladaTriangle = R"(  <library_geometries>
    <geometry id="tri-mesh" name="tri"><mesh>
      <source id="tri-positions"><float_array id="tri-positions-array" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#tri-positions-array" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="tri-vertices"><input semantic="POSITION" source="#tri-positions"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#tri-vertices" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="Scene" name="Scene">
      <node id="tri" name="tri"><instance_geometry url="#tri-mesh"/></node>
)";

// A DirectX .x quad (0,0,0)-(1,1,0) whose material names `texture` (a file name) and whose four
// corners have the texture coordinates `uvs` ("u;v;" each, in the file's v-down space; assimp's
// X reader turns them into its v-up ones).
inline std::string texturedQuadX(const std::string& texture,
                                 const std::string& uvs = "0.0;1.0;, 1.0;1.0;, 1.0;0.0;, 0.0;0.0;") {
    return R"(xof 0302txt 0064
Material Painted {
 1.0;1.0;1.0;1.0;;
 0.0;
 0.0;0.0;0.0;;
 0.0;0.0;0.0;;
 TextureFilename { ")" + texture + R"("; }
}
Mesh quad {
 4;
 0.0;0.0;0.0;,
 1.0;0.0;0.0;,
 1.0;1.0;0.0;,
 0.0;1.0;0.0;;
 2;
 3;0,1,2;,
 3;0,2,3;;
 MeshMaterialList { 1; 2; 0, 0;; { Painted } }
 MeshTextureCoords { 4; )" + uvs + R"(; }
}
)";
}

#define EXPECT_IMPORT_ERROR(result, file, element)                                   \
    do {                                                                             \
        const auto& r_ = (result);                                                   \
        ASSERT_FALSE(r_.isOk()) << "import unexpectedly succeeded";                  \
        EXPECT_NE(r_.message().find(file), std::string::npos) << r_.message();       \
        EXPECT_NE(r_.message().find(element), std::string::npos) << r_.message();    \
    } while (0)

}  // namespace vastray::test

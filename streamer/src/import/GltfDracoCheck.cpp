#include "import/GltfDracoCheck.h"

#include <draco/compression/decode.h>

#include "import/GltfLoader.h"
#include "import/ImportCommon.h"

namespace vastray::import {
namespace {

std::string decodeBase64(std::string_view in) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        return c == '+' ? 62 : c == '/' ? 63 : -1;
    };
    std::string out;
    uint32_t bits = 0;
    int count = 0;
    for (char c : in) {
        const int v = value(c);
        if (v < 0) continue;  // padding
        bits = (bits << 6) | uint32_t(v);
        if ((count += 6) >= 8) out += char((bits >> (count -= 8)) & 0xff);
    }
    return out;
}

// tinygltf URL-decodes external URIs before opening them; so do we.
std::string urlDecode(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) && std::isxdigit(uint8_t(uri[i + 2]))) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

Result<std::string> bufferBytes(const nlohmann::json& buffer, std::string_view glbBin, const std::string& folder) {
    const std::string uri = buffer.value("uri", std::string());
    if (uri.empty()) return std::string(glbBin);
    if (uri.rfind("data:", 0) == 0) {
        const size_t comma = uri.find(";base64,");
        if (comma == std::string::npos) return Status::error("buffer data: URI is not base64");
        return decodeBase64(std::string_view(uri).substr(comma + 8));
    }
    const std::string path = urlDecode(uri);
    std::string why;
    if (!isSafeRelativeUri(path, why)) return Status::error("uri '" + path + "' " + why);
    if (!insideFolder(folder, folder + "/" + path))
        return Status::error("uri '" + path + "' resolves outside the model folder (a link)");
    auto bytes = readWholeFile(folder + "/" + path);
    if (!bytes) return bytes.status();
    return std::string(bytes->begin(), bytes->end());
}

Status checkPrimitive(const nlohmann::json& doc, const nlohmann::json& ext, std::string_view glbBin,
                      const std::string& folder) {
    const auto& view = doc["bufferViews"][ext["bufferView"].get<size_t>()];
    auto bytes = bufferBytes(doc["buffers"][view["buffer"].get<size_t>()], glbBin, folder);
    if (!bytes) return bytes.status();
    const uint64_t offset = view.value("byteOffset", uint64_t(0)), length = view.value("byteLength", uint64_t(0));
    if (offset > bytes->size() || length > bytes->size() - offset)
        return Status::error("KHR_draco_mesh_compression: bufferView exceeds the buffer's data");
    draco::DecoderBuffer buffer;
    buffer.Init(bytes->data() + offset, length);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) return Status::error("KHR_draco_mesh_compression: " + decoded.status().error_msg_string());
    const draco::Mesh& mesh = *decoded.value();
    for (const auto& [name, id] : ext["attributes"].items()) {
        if (!mesh.GetAttributeByUniqueId(id.get<uint32_t>()))
            return Status::error("KHR_draco_mesh_compression: attribute " + name + " id " + id.dump() +
                                 " is not in the Draco bitstream");
    }
    return Status::ok();
}

}  // namespace

Status checkDracoAttributes(const nlohmann::json& doc, std::string_view glbBin, const std::string& folder) {
    const auto& meshes = doc.value("meshes", nlohmann::json::array());
    for (size_t m = 0; m < meshes.size(); ++m) {
        const auto& prims = meshes[m].value("primitives", nlohmann::json::array());
        for (size_t p = 0; p < prims.size(); ++p) {
            const auto& prim = prims[p];
            if (!prim.contains("extensions") || !prim["extensions"].contains("KHR_draco_mesh_compression")) continue;
            const Status s = checkPrimitive(doc, prim["extensions"]["KHR_draco_mesh_compression"], glbBin, folder);
            if (!s.isOk()) return s.withContext("mesh " + std::to_string(m) + " primitive " + std::to_string(p) + ": ");
        }
    }
    return Status::ok();
}

}  // namespace vastray::import

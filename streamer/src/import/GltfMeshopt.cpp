#include "import/GltfMeshopt.h"

#include <meshoptimizer.h>

namespace vastray::import {
namespace {

constexpr const char* kExtension = "EXT_meshopt_compression";

const nlohmann::json* extensionOf(const nlohmann::json& object) {
    if (!object.is_object() || !object.contains("extensions")) return nullptr;
    const auto& extensions = object["extensions"];
    if (!extensions.is_object() || !extensions.contains(kExtension)) return nullptr;
    return &extensions[kExtension];
}

bool unsignedField(const nlohmann::json& object, const char* key, uint64_t& out, bool required) {
    if (!object.contains(key)) return !required;
    const auto& v = object[key];
    if (!v.is_number_integer() || v.get<int64_t>() < 0) return false;
    out = v.get<uint64_t>();
    return true;
}

Status checkView(const nlohmann::json& ext, size_t bufferCount, MeshoptView& v, uint64_t& buffer,
                 uint64_t& offset, uint64_t& length) {
    if (!ext.is_object()) return Status::error("is not an object");
    if (!unsignedField(ext, "buffer", buffer, true) || buffer >= bufferCount)
        return Status::error("buffer is missing or names no buffer");
    if (!unsignedField(ext, "byteOffset", offset, false)) return Status::error("byteOffset is not a non-negative integer");
    if (!unsignedField(ext, "byteLength", length, true)) return Status::error("byteLength is missing or negative");
    if (!unsignedField(ext, "byteStride", v.stride, true) || v.stride == 0 || v.stride > 256)
        return Status::error("byteStride is missing or outside [1, 256]");
    if (!unsignedField(ext, "count", v.count, true)) return Status::error("count is missing or negative");
    v.mode = ext.value("mode", nlohmann::json()).is_string() ? ext["mode"].get<std::string>() : "";
    v.filter = ext.value("filter", nlohmann::json("NONE")).is_string() ? ext.value("filter", std::string("NONE")) : "";
    if (v.mode == "ATTRIBUTES") {
        if (v.stride % 4 != 0) return Status::error("byteStride " + std::to_string(v.stride) + " is not a multiple of 4");
    } else if (v.mode == "TRIANGLES" || v.mode == "INDICES") {
        if (v.stride != 2 && v.stride != 4) return Status::error("index byteStride must be 2 or 4");
        if (v.mode == "TRIANGLES" && v.count % 3 != 0) return Status::error("TRIANGLES count is not a multiple of 3");
        if (v.filter != "NONE") return Status::error("filter " + v.filter + " applies to ATTRIBUTES only");
    } else {
        return Status::error("mode '" + v.mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
    }
    if (v.filter != "NONE" && v.filter != "OCTAHEDRAL" && v.filter != "QUATERNION" && v.filter != "EXPONENTIAL")
        return Status::error("filter '" + v.filter + "' is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    if ((v.filter == "OCTAHEDRAL" && v.stride != 4 && v.stride != 8) || (v.filter == "QUATERNION" && v.stride != 8))
        return Status::error("filter " + v.filter + " does not allow byteStride " + std::to_string(v.stride));
    if (v.count > (uint64_t(1) << 32) || v.count * v.stride > kMaxMeshoptExpansion * length + (1u << 16))
        return Status::error(std::to_string(v.count) + " elements of " + std::to_string(v.stride) +
                             " bytes from " + std::to_string(length) + " compressed bytes exceed the expansion limit of " +
                             std::to_string(kMaxMeshoptExpansion) + "x");
    return Status::ok();
}

}  // namespace

Status prepareMeshopt(nlohmann::json& doc, std::vector<MeshoptView>& views) {
    if (!doc.contains("bufferViews")) return Status::ok();
    auto& bufferViews = doc["bufferViews"];
    const size_t bufferCount = doc.contains("buffers") ? doc["buffers"].size() : 0;
    for (size_t i = 0; i < bufferViews.size(); ++i) {
        const nlohmann::json* ext = extensionOf(bufferViews[i]);
        if (!ext) continue;
        MeshoptView v;
        v.view = i;
        uint64_t buffer = 0, offset = 0, length = 0;
        if (Status s = checkView(*ext, bufferCount, v, buffer, offset, length); !s.isOk())
            return s.withContext("bufferView " + std::to_string(i) + ": " + kExtension + ": ");
        auto& view = bufferViews[i];
        view["buffer"] = buffer;  // the compressed bytes, until decodeMeshopt
        view["byteOffset"] = offset;
        view["byteLength"] = length;
        view.erase("byteStride");
        view["extensions"].erase(kExtension);
        views.push_back(v);
    }
    if (views.empty()) return Status::ok();
    // Fallback buffers hold no data when the file has only the compressed form; tinygltf
    // wants data for every buffer (and refuses an empty data: URI): four zero bytes.
    for (auto& buffer : doc["buffers"]) {
        const nlohmann::json* ext = extensionOf(buffer);
        if (ext && ext->is_object() && ext->value("fallback", false) && !buffer.contains("uri")) {
            buffer["uri"] = "data:application/octet-stream;base64,AAAAAA==";
            buffer["byteLength"] = 4;
        }
    }
    return Status::ok();
}

Status decodeMeshopt(tinygltf::Model& model, const std::vector<MeshoptView>& views) {
    for (const MeshoptView& v : views) {
        const std::string where = "bufferView " + std::to_string(v.view) + ": " + kExtension + ": ";
        tinygltf::BufferView& view = model.bufferViews[v.view];
        if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
            return Status::error(where + "buffer does not exist");
        const std::vector<unsigned char>& source = model.buffers[view.buffer].data;
        if (view.byteOffset > source.size() || view.byteLength > source.size() - view.byteOffset)
            return Status::error(where + "compressed bytes exceed buffer " + std::to_string(view.buffer));
        const unsigned char* src = source.data() + view.byteOffset;
        std::vector<unsigned char> decoded(v.count * v.stride);
        int rc = 0;
        if (v.mode == "ATTRIBUTES") rc = meshopt_decodeVertexBuffer(decoded.data(), v.count, v.stride, src, view.byteLength);
        else if (v.mode == "TRIANGLES") rc = meshopt_decodeIndexBuffer(decoded.data(), v.count, v.stride, src, view.byteLength);
        else rc = meshopt_decodeIndexSequence(decoded.data(), v.count, v.stride, src, view.byteLength);
        if (rc != 0) return Status::error(where + "the " + v.mode + " data does not decode (meshoptimizer error " + std::to_string(rc) + ")");
        if (v.filter == "OCTAHEDRAL") meshopt_decodeFilterOct(decoded.data(), v.count, v.stride);
        if (v.filter == "QUATERNION") meshopt_decodeFilterQuat(decoded.data(), v.count, v.stride);
        if (v.filter == "EXPONENTIAL") meshopt_decodeFilterExp(decoded.data(), v.count, v.stride);
        tinygltf::Buffer buffer;
        buffer.data = std::move(decoded);
        model.buffers.push_back(std::move(buffer));
        view.buffer = int(model.buffers.size() - 1);
        view.byteOffset = 0;
        view.byteLength = v.count * v.stride;
        view.byteStride = v.mode == "ATTRIBUTES" ? v.stride : 0;
    }
    return Status::ok();
}

}  // namespace vastray::import

#include "import/GltfAccessor.h"

#include "import/ImportCommon.h"

#include <algorithm>
#include <cstring>

namespace vastray::import {
namespace {

struct AccessorView {
    const unsigned char* base = nullptr;  // first element
    size_t stride = 0;
    size_t count = 0;
};

int componentSize(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

Status locate(const tinygltf::Model& model, int index, int components, AccessorView& out) {
    const std::string what = "accessor " + std::to_string(index) + ": ";
    if (index < 0 || size_t(index) >= model.accessors.size()) return Status::error(what + "does not exist");
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.sparse.isSparse) return Status::error(what + "sparse accessors are not supported");
    const int size = componentSize(a.componentType);
    if (size == 0) return Status::error(what + "bad component type " + std::to_string(a.componentType));
    out.count = a.count;
    if (a.count == 0) return Status::ok();
    if (a.bufferView < 0 || size_t(a.bufferView) >= model.bufferViews.size())
        return Status::error(what + "bufferView " + std::to_string(a.bufferView) + " does not exist");
    const tinygltf::BufferView& v = model.bufferViews[a.bufferView];
    if (v.buffer < 0 || size_t(v.buffer) >= model.buffers.size())
        return Status::error(what + "buffer " + std::to_string(v.buffer) + " does not exist");
    const std::vector<unsigned char>& data = model.buffers[v.buffer].data;
    const uint64_t element = uint64_t(size) * components;
    const uint64_t stride = v.byteStride ? v.byteStride : element;
    if (stride < element) return Status::error(what + "byteStride smaller than one element");
    const uint64_t viewEnd = uint64_t(v.byteOffset) + v.byteLength;
    const uint64_t needed = uint64_t(a.byteOffset) + stride * (a.count - 1) + element;
    if (viewEnd > data.size() || needed > v.byteLength || a.count > data.size())
        return Status::error(what + std::to_string(a.count) + " elements do not fit in bufferView " +
                             std::to_string(a.bufferView) + " / buffer " + std::to_string(v.buffer));
    out.base = data.data() + v.byteOffset + a.byteOffset;
    out.stride = stride;
    return Status::ok();
}

template <typename T>
T load(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

// KHR_mesh_quantization: normalized integers map to [-1,1] or [0,1] (glTF 2.0 spec 3.11).
double component(const unsigned char* p, int type, bool normalized) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: return normalized ? std::max(load<int8_t>(p) / 127.0, -1.0) : load<int8_t>(p);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? load<uint8_t>(p) / 255.0 : load<uint8_t>(p);
        case TINYGLTF_COMPONENT_TYPE_SHORT: return normalized ? std::max(load<int16_t>(p) / 32767.0, -1.0) : load<int16_t>(p);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return normalized ? load<uint16_t>(p) / 65535.0 : load<uint16_t>(p);
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return load<uint32_t>(p);
        default: return load<float>(p);
    }
}

}  // namespace

Status readVec3Accessor(const tinygltf::Model& model, int index, std::vector<double>& xyz, const char* what) {
    AccessorView view;
    if (Status s = locate(model, index, 3, view); !s.isOk()) return s;
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.type != TINYGLTF_TYPE_VEC3)
        return Status::error("accessor " + std::to_string(index) + ": " + what + " is not VEC3");
    const int size = componentSize(a.componentType);
    xyz.resize(view.count * 3);
    for (size_t i = 0; i < view.count; ++i)
        for (int c = 0; c < 3; ++c)
            xyz[i * 3 + c] = component(view.base + i * view.stride + c * size, a.componentType, a.normalized);
    return Status::ok();
}

Status readColorAccessor(const tinygltf::Model& model, int index, std::vector<double>& rgb) {
    if (index < 0 || size_t(index) >= model.accessors.size())
        return Status::error("accessor " + std::to_string(index) + ": does not exist");
    const tinygltf::Accessor& a = model.accessors[index];
    const int t = a.componentType;
    const bool integer = t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    if ((a.type != TINYGLTF_TYPE_VEC3 && a.type != TINYGLTF_TYPE_VEC4) ||
        !(t == TINYGLTF_COMPONENT_TYPE_FLOAT || (integer && a.normalized)))
        return Status::error("accessor " + std::to_string(index) +
                             ": COLOR_0 must be VEC3 or VEC4 of floats or normalized unsigned bytes or shorts");
    const int components = a.type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
    AccessorView view;
    if (Status s = locate(model, index, components, view); !s.isOk()) return s;
    const int size = componentSize(t);
    rgb.resize(view.count * 3);
    for (size_t i = 0; i < view.count; ++i)
        for (int c = 0; c < 3; ++c)
            rgb[i * 3 + c] = std::clamp(component(view.base + i * view.stride + c * size, t, true), 0.0, 1.0);
    return Status::ok();
}

Status readUvAccessor(const tinygltf::Model& model, int index, const std::string& what, std::vector<double>& uv) {
    const std::string where = "accessor " + std::to_string(index) + ": ";
    if (index < 0 || size_t(index) >= model.accessors.size()) return Status::error(where + "does not exist");
    const tinygltf::Accessor& a = model.accessors[index];
    const int t = a.componentType;
    const bool integer = t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || t == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    if (a.type != TINYGLTF_TYPE_VEC2 || !(t == TINYGLTF_COMPONENT_TYPE_FLOAT || (integer && a.normalized)))
        return Status::error(where + what + " must be VEC2 of floats or normalized unsigned bytes or shorts");
    AccessorView view;
    if (Status s = locate(model, index, 2, view); !s.isOk()) return s;
    const int size = componentSize(t);
    uv.resize(view.count * 2);
    for (size_t i = 0; i < view.count; ++i) {
        for (int c = 0; c < 2; ++c) uv[i * 2 + c] = component(view.base + i * view.stride + c * size, t, true);
        if (const std::string problem = uvProblem(uv[i * 2], uv[i * 2 + 1]); !problem.empty())
            return Status::error(where + what + " element " + std::to_string(i) + " " + problem);
    }
    return Status::ok();
}

Status readIndexAccessor(const tinygltf::Model& model, int index, std::vector<uint32_t>& indices) {
    AccessorView view;
    if (Status s = locate(model, index, 1, view); !s.isOk()) return s;
    const tinygltf::Accessor& a = model.accessors[index];
    const int t = a.componentType;
    if (a.type != TINYGLTF_TYPE_SCALAR ||
        (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        return Status::error("accessor " + std::to_string(index) + ": indices must be unsigned 8/16/32-bit scalars");
    indices.resize(view.count);
    for (size_t i = 0; i < view.count; ++i)
        indices[i] = static_cast<uint32_t>(component(view.base + i * view.stride, t, false));
    return Status::ok();
}

}  // namespace vastray::import

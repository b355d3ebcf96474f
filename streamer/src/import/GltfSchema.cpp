#include "import/GltfSchema.h"

#include <initializer_list>
#include <string>
#include <utility>

namespace vastray::import {
namespace {

using Json = nlohmann::json;

enum class Kind { Object, ObjectArray, Index, IndexArray, Number, NumberArray, Bool, String, StringArray, IndexMap };

struct Schema;

struct Field {
    const char* name;
    Kind kind;
    const Schema* schema = nullptr;  // for Object and ObjectArray
    size_t length = 0;               // NumberArray: 0 = any length
    bool required = false;
};

struct Schema {
    std::initializer_list<Field> fields;
};

const char* kindName(Kind kind) {
    switch (kind) {
        case Kind::Object: return "an object";
        case Kind::ObjectArray: return "an array of objects";
        case Kind::Index: return "a non-negative integer";
        case Kind::IndexArray: return "an array of non-negative integers";
        case Kind::Number: return "a number";
        case Kind::NumberArray: return "an array of numbers";
        case Kind::Bool: return "a boolean";
        case Kind::String: return "a string";
        case Kind::StringArray: return "an array of strings";
        case Kind::IndexMap: return "an object of non-negative integers";
    }
    return "?";
}

std::string found(const Json& v) {
    std::string text = v.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return std::string(v.type_name()) + " " + text;
}

bool isIndex(const Json& v) { return v.is_number_integer() && v.get<int64_t>() >= 0; }

Status check(const Json& object, const Schema& schema, const std::string& path);

Status wrongType(const std::string& path, Kind kind, const Json& v) {
    return Status::error(path + ": expected " + kindName(kind) + ", found " + found(v));
}

// Every extension's value is an object (glTF 2.0 spec 3.12); their contents are the
// extensions' own business (GltfLoader checks the ones it reads).
Status checkExtensions(const Json& object, const std::string& path) {
    if (!object.contains("extensions")) return Status::ok();
    const Json& ext = object["extensions"];
    if (!ext.is_object()) return wrongType(path + "/extensions", Kind::Object, ext);
    for (const auto& [name, value] : ext.items())
        if (!value.is_object()) return wrongType(path + "/extensions/" + name, Kind::Object, value);
    return Status::ok();
}

Status checkField(const Json& v, const Field& f, const std::string& path) {
    switch (f.kind) {
        case Kind::Object:
            if (!v.is_object()) return wrongType(path, f.kind, v);
            return f.schema ? check(v, *f.schema, path) : checkExtensions(v, path);
        case Kind::ObjectArray:
            if (!v.is_array()) return wrongType(path, f.kind, v);
            for (size_t i = 0; i < v.size(); ++i) {
                const std::string at = path + "/" + std::to_string(i);
                if (!v[i].is_object()) return wrongType(at, Kind::Object, v[i]);
                if (Status s = check(v[i], *f.schema, at); !s.isOk()) return s;
            }
            return Status::ok();
        case Kind::Index:
            return isIndex(v) ? Status::ok() : wrongType(path, f.kind, v);
        case Kind::IndexArray:
            if (!v.is_array()) return wrongType(path, f.kind, v);
            for (size_t i = 0; i < v.size(); ++i)
                if (!isIndex(v[i])) return wrongType(path + "/" + std::to_string(i), Kind::Index, v[i]);
            return Status::ok();
        case Kind::Number:
            return v.is_number() ? Status::ok() : wrongType(path, f.kind, v);
        case Kind::NumberArray:
            if (!v.is_array()) return wrongType(path, f.kind, v);
            if (f.length && v.size() != f.length)
                return Status::error(path + ": expected " + std::to_string(f.length) + " numbers, found " +
                                     std::to_string(v.size()));
            for (size_t i = 0; i < v.size(); ++i)
                if (!v[i].is_number()) return wrongType(path + "/" + std::to_string(i), Kind::Number, v[i]);
            return Status::ok();
        case Kind::Bool:
            return v.is_boolean() ? Status::ok() : wrongType(path, f.kind, v);
        case Kind::String:
            return v.is_string() ? Status::ok() : wrongType(path, f.kind, v);
        case Kind::StringArray:
            if (!v.is_array()) return wrongType(path, f.kind, v);
            for (size_t i = 0; i < v.size(); ++i)
                if (!v[i].is_string()) return wrongType(path + "/" + std::to_string(i), Kind::String, v[i]);
            return Status::ok();
        case Kind::IndexMap:
            if (!v.is_object()) return wrongType(path, f.kind, v);
            for (const auto& [key, value] : v.items())
                if (!isIndex(value)) return wrongType(path + "/" + key, Kind::Index, value);
            return Status::ok();
    }
    return Status::ok();
}

Status check(const Json& object, const Schema& schema, const std::string& path) {
    for (const Field& f : schema.fields) {
        const std::string at = path + "/" + f.name;
        if (!object.contains(f.name)) {
            if (f.required) return Status::error(at + ": required field is missing");
            continue;
        }
        if (Status s = checkField(object[f.name], f, at); !s.isOk()) return s;
    }
    return checkExtensions(object, path);
}

// The glTF 2.0 schema, for the fields the loader and tinygltf read.
const Schema kTextureInfo{{{"index", Kind::Index, nullptr, 0, true}, {"texCoord", Kind::Index},
                           {"scale", Kind::Number}, {"strength", Kind::Number}}};
const Schema kPbr{{{"baseColorFactor", Kind::NumberArray, nullptr, 4}, {"baseColorTexture", Kind::Object, &kTextureInfo},
                   {"metallicFactor", Kind::Number}, {"roughnessFactor", Kind::Number},
                   {"metallicRoughnessTexture", Kind::Object, &kTextureInfo}}};
const Schema kMaterial{{{"name", Kind::String}, {"pbrMetallicRoughness", Kind::Object, &kPbr},
                        {"normalTexture", Kind::Object, &kTextureInfo}, {"occlusionTexture", Kind::Object, &kTextureInfo},
                        {"emissiveTexture", Kind::Object, &kTextureInfo}, {"emissiveFactor", Kind::NumberArray, nullptr, 3},
                        {"alphaMode", Kind::String}, {"alphaCutoff", Kind::Number}, {"doubleSided", Kind::Bool}}};
const Schema kMorphTarget{{}};
const Schema kPrimitive{{{"attributes", Kind::IndexMap, nullptr, 0, true}, {"indices", Kind::Index},
                                    {"material", Kind::Index}, {"mode", Kind::Index},
                                    {"targets", Kind::ObjectArray, &kMorphTarget}}};
const Schema kMesh{{{"primitives", Kind::ObjectArray, &kPrimitive, 0, true}, {"weights", Kind::NumberArray},
                    {"name", Kind::String}}};
const Schema kNode{{{"camera", Kind::Index}, {"children", Kind::IndexArray}, {"skin", Kind::Index},
                    {"matrix", Kind::NumberArray, nullptr, 16}, {"mesh", Kind::Index},
                    {"rotation", Kind::NumberArray, nullptr, 4}, {"scale", Kind::NumberArray, nullptr, 3},
                    {"translation", Kind::NumberArray, nullptr, 3}, {"weights", Kind::NumberArray}, {"name", Kind::String}}};
const Schema kScene{{{"nodes", Kind::IndexArray}, {"name", Kind::String}}};
const Schema kSparse{{{"count", Kind::Index, nullptr, 0, true}}};
const Schema kAccessor{{{"bufferView", Kind::Index}, {"byteOffset", Kind::Index},
                        {"componentType", Kind::Index, nullptr, 0, true}, {"normalized", Kind::Bool},
                        {"count", Kind::Index, nullptr, 0, true}, {"type", Kind::String, nullptr, 0, true},
                        {"max", Kind::NumberArray}, {"min", Kind::NumberArray}, {"sparse", Kind::Object, &kSparse}}};
const Schema kBufferView{{{"buffer", Kind::Index, nullptr, 0, true}, {"byteOffset", Kind::Index},
                          {"byteLength", Kind::Index, nullptr, 0, true}, {"byteStride", Kind::Index},
                          {"target", Kind::Index}}};
const Schema kBuffer{{{"uri", Kind::String}, {"byteLength", Kind::Index, nullptr, 0, true}}};
const Schema kImage{{{"uri", Kind::String}, {"mimeType", Kind::String}, {"bufferView", Kind::Index}}};
const Schema kTexture{{{"sampler", Kind::Index}, {"source", Kind::Index}}};
const Schema kSampler{{{"magFilter", Kind::Index}, {"minFilter", Kind::Index}, {"wrapS", Kind::Index},
                       {"wrapT", Kind::Index}}};
const Schema kPerspective{{{"aspectRatio", Kind::Number}, {"yfov", Kind::Number, nullptr, 0, true},
                           {"zfar", Kind::Number}, {"znear", Kind::Number, nullptr, 0, true}}};
const Schema kOrthographic{{{"xmag", Kind::Number, nullptr, 0, true}, {"ymag", Kind::Number, nullptr, 0, true},
                            {"zfar", Kind::Number, nullptr, 0, true}, {"znear", Kind::Number, nullptr, 0, true}}};
const Schema kCamera{{{"type", Kind::String, nullptr, 0, true}, {"perspective", Kind::Object, &kPerspective},
                      {"orthographic", Kind::Object, &kOrthographic}}};
const Schema kAsset{{{"version", Kind::String, nullptr, 0, true}, {"minVersion", Kind::String},
                     {"generator", Kind::String}, {"copyright", Kind::String}}};
const Schema kRoot{{{"asset", Kind::Object, &kAsset, 0, true}, {"accessors", Kind::ObjectArray, &kAccessor},
                    {"bufferViews", Kind::ObjectArray, &kBufferView}, {"buffers", Kind::ObjectArray, &kBuffer},
                    {"meshes", Kind::ObjectArray, &kMesh}, {"nodes", Kind::ObjectArray, &kNode},
                    {"scenes", Kind::ObjectArray, &kScene}, {"scene", Kind::Index},
                    {"materials", Kind::ObjectArray, &kMaterial}, {"textures", Kind::ObjectArray, &kTexture},
                    {"images", Kind::ObjectArray, &kImage}, {"samplers", Kind::ObjectArray, &kSampler},
                    {"cameras", Kind::ObjectArray, &kCamera}, {"extensionsUsed", Kind::StringArray},
                    {"extensionsRequired", Kind::StringArray}}};

// KHR_lights_punctual: the lights in the document's extension, a node's reference to one.
const Schema kSpot{{{"innerConeAngle", Kind::Number}, {"outerConeAngle", Kind::Number}}};
const Schema kLight{{{"type", Kind::String, nullptr, 0, true}, {"name", Kind::String},
                     {"color", Kind::NumberArray, nullptr, 3}, {"intensity", Kind::Number}, {"range", Kind::Number},
                     {"spot", Kind::Object, &kSpot}}};
const Schema kLightsExtension{{{"lights", Kind::ObjectArray, &kLight, 0, true}}};
const Schema kNodeLight{{{"light", Kind::Index, nullptr, 0, true}}};
constexpr const char* kLightsPunctual = "KHR_lights_punctual";

// The material extensions the importer reads (their values' ranges: finalizeMesh).
const Schema kSpecularExtension{{{"specularFactor", Kind::Number}, {"specularTexture", Kind::Object, &kTextureInfo},
                                 {"specularColorFactor", Kind::NumberArray, nullptr, 3},
                                 {"specularColorTexture", Kind::Object, &kTextureInfo}}};
const Schema kClearcoatExtension{{{"clearcoatFactor", Kind::Number}, {"clearcoatTexture", Kind::Object, &kTextureInfo},
                                  {"clearcoatRoughnessFactor", Kind::Number},
                                  {"clearcoatRoughnessTexture", Kind::Object, &kTextureInfo},
                                  {"clearcoatNormalTexture", Kind::Object, &kTextureInfo}}};
const Schema kIorExtension{{{"ior", Kind::Number}}};
const std::pair<const char*, const Schema*> kMaterialExtensions[] = {{"KHR_materials_specular", &kSpecularExtension},
                                                                     {"KHR_materials_clearcoat", &kClearcoatExtension},
                                                                     {"KHR_materials_ior", &kIorExtension}};

Status checkMaterialExtensionTypes(const Json& doc) {
    if (!doc.contains("materials")) return Status::ok();
    const Json& materials = doc["materials"];
    for (size_t i = 0; i < materials.size(); ++i) {
        const auto ext = materials[i].find("extensions");
        if (ext == materials[i].end()) continue;
        for (const auto& [name, schema] : kMaterialExtensions)
            if (const auto found = ext->find(name); found != ext->end())
                VASTRAY_TRY(check(*found, *schema, "JSON /materials/" + std::to_string(i) + "/extensions/" + name));
    }
    return Status::ok();
}

// After the root's check: every object on the way is what the schema said.
Status checkLightTypes(const Json& doc) {
    const auto extensionOf = [](const Json& object) -> const Json* {
        const auto ext = object.find("extensions");
        if (ext == object.end()) return nullptr;
        const auto found = ext->find(kLightsPunctual);
        return found == ext->end() ? nullptr : &*found;
    };
    if (const Json* lights = extensionOf(doc))
        VASTRAY_TRY(check(*lights, kLightsExtension, std::string("JSON /extensions/") + kLightsPunctual));
    if (!doc.contains("nodes")) return Status::ok();
    const Json& nodes = doc["nodes"];
    for (size_t i = 0; i < nodes.size(); ++i)
        if (const Json* light = extensionOf(nodes[i]))
            VASTRAY_TRY(check(*light, kNodeLight, "JSON /nodes/" + std::to_string(i) + "/extensions/" + kLightsPunctual));
    return Status::ok();
}

}  // namespace

Status checkGltfTypes(const nlohmann::json& doc) {
    if (!doc.is_object()) return Status::error("JSON: the top level is " + found(doc) + ", not an object");
    VASTRAY_TRY(check(doc, kRoot, "JSON "));
    VASTRAY_TRY(checkMaterialExtensionTypes(doc));
    return checkLightTypes(doc);
}

}  // namespace vastray::import

#include "import/GltfLoader.h"

#include <cstring>
#include <filesystem>
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

#include "import/GltfDracoCheck.h"
#include "import/GltfMeshopt.h"
#include "import/GltfSchema.h"
#include "import/ImportCommon.h"

namespace vastray::import {
namespace {

// KHR_texture_transform is applied to every map (GltfTextures); quantized (normalized integer)
// positions are read by GltfAccessor.
const std::set<std::string> kSupportedRequired = {
    "KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization", "KHR_materials_emissive_strength",
    "KHR_materials_specular",     "KHR_materials_clearcoat", "KHR_materials_ior",     "KHR_texture_transform",
    "KHR_lights_punctual",        "KHR_texture_basisu"};

// glTF's own structure nests about 6 deep (extensions and extras a few more). tinygltf and
// nlohmann walk the JSON recursively: 20,000 levels (40 KB of '[') overflowed the stack.
constexpr int kMaxJsonDepth = 64;

// The deepest nesting of arrays and objects, counted outside strings, stopping as soon as
// it passes `limit` (the text is not parsed yet: malformed JSON is reported by the parser).
int jsonDepth(std::string_view text, int limit) {
    int depth = 0, deepest = 0;
    bool inString = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\') ++i;
            else if (c == '"') inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            deepest = std::max(deepest, ++depth);
            if (deepest > limit) break;
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
    return deepest;
}

// Views that interleave attributes have a stride; glTF 2.0 (3.6.2.3) allows 4..252, a
// multiple of 4. tinygltf kept a negative one as a huge unsigned value.
Status checkBufferViews(const nlohmann::json& doc) {
    const auto& views = doc.value("bufferViews", nlohmann::json::array());
    if (!views.is_array()) return Status::error("bufferViews is not an array");
    for (size_t i = 0; i < views.size(); ++i) {
        if (!views[i].is_object() || !views[i].contains("byteStride")) continue;
        const auto& stride = views[i]["byteStride"];
        if (!stride.is_number_integer() || stride.get<int64_t>() < 4 || stride.get<int64_t>() > 252 ||
            stride.get<int64_t>() % 4 != 0)
            return Status::error("bufferView " + std::to_string(i) + ": byteStride " + stride.dump() +
                                 " is not a multiple of 4 in [4, 252]");
    }
    return Status::ok();
}

struct Sandbox {
    std::string folder;     // the model's folder, as passed to tinygltf as base_dir
    std::string violation;  // first forbidden URI seen, reported instead of tinygltf's message
};

// tinygltf hands us base_dir joined with the URI; also "./uri" (its CWD fallback), refused.
bool allowedPath(const std::string& path, Sandbox& box) {
    const std::string prefix = box.folder + "/";
    if (path.compare(0, prefix.size(), prefix) != 0) return false;
    const std::string uri = path.substr(prefix.size());
    std::string why;
    if (!isSafeRelativeUri(uri, why)) {
        if (box.violation.empty()) box.violation = "uri '" + uri + "' " + why;
        return false;
    }
    if (insideFolder(box.folder, path)) return true;
    if (box.violation.empty()) box.violation = "uri '" + uri + "' resolves outside the model folder (a link)";
    return false;
}

bool sandboxFileExists(const std::string& path, void* user) {
    std::error_code ec;
    return allowedPath(path, *static_cast<Sandbox*>(user)) && std::filesystem::is_regular_file(path, ec);
}

std::string sandboxExpand(const std::string& path, void*) { return path; }

bool sandboxRead(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    if (!allowedPath(path, *static_cast<Sandbox*>(user))) {
        if (err) *err = "refused";
        return false;
    }
    auto bytes = readWholeFile(path);
    if (!bytes) {
        if (err) *err = bytes.message();
        return false;
    }
    out->assign(bytes->begin(), bytes->end());
    return true;
}

bool sandboxWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err = "writing is disabled";
    return false;
}

// Images are kept as tinygltf hands them over, encoded (from a file, a data URI or a buffer view):
// GltfTextures.cpp names them, and import decodes only those a material's map reads.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (bytes && size > 0) image->image.assign(bytes, bytes + size);
    return true;
}

uint32_t readU32(const std::vector<char>& b, size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;  // GLB is little endian, as are the hosts vastray runs on
}

bool isGlbVersion1(const std::vector<char>& bytes) {
    return bytes.size() >= 8 && std::memcmp(bytes.data(), "glTF", 4) == 0 && readU32(bytes, 4) == 1;
}

// asset.version "1.x" (or the number 1, as collada2gltf wrote it), or, without a version,
// glTF 1.0's dictionaries where 2.0 has arrays.
bool isJsonVersion1(const nlohmann::json& doc) {
    if (!doc.is_object()) return false;
    const auto& asset = doc.value("asset", nlohmann::json());
    const auto& version = asset.is_object() ? asset.value("version", nlohmann::json()) : nlohmann::json();
    if (version.is_string()) return version.get<std::string>().rfind("1.", 0) == 0;
    if (version.is_number()) return version.get<double>() >= 1.0 && version.get<double>() < 2.0;
    for (const char* key : {"meshes", "accessors", "bufferViews", "nodes"})
        if (doc.contains(key) && doc[key].is_object()) return true;
    return false;
}

// Finds the JSON chunk and, when present, the BIN chunk that follows it.
Status checkGlbHeader(const std::vector<char>& b, std::string_view& json, std::string_view& bin) {
    if (b.size() < 20) return Status::error("GLB header: file has " + std::to_string(b.size()) + " bytes, need at least 20");
    if (std::memcmp(b.data(), "glTF", 4) != 0) return Status::error("GLB header: bad magic (not 'glTF')");
    if (readU32(b, 4) != 2) return Status::error("GLB header: version " + std::to_string(readU32(b, 4)) + " is not 2");
    const uint64_t length = readU32(b, 8);
    if (length > b.size() || length < 20)
        return Status::error("GLB header: declared length " + std::to_string(length) + " but file has " +
                             std::to_string(b.size()) + " bytes");
    const uint64_t jsonLength = readU32(b, 12);
    if (readU32(b, 16) != 0x4E4F534Au) return Status::error("GLB header: first chunk is not JSON");
    if (jsonLength == 0 || 20 + jsonLength > length)
        return Status::error("GLB header: JSON chunk length " + std::to_string(jsonLength) + " exceeds the file");
    json = std::string_view(b.data() + 20, jsonLength);
    const uint64_t binHeader = 20 + jsonLength;
    if (binHeader + 8 <= length && readU32(b, binHeader + 4) == 0x004E4942u) {
        const uint64_t binLength = readU32(b, binHeader);
        if (binHeader + 8 + binLength > length)
            return Status::error("GLB header: BIN chunk length " + std::to_string(binLength) + " exceeds the file");
        bin = std::string_view(b.data() + binHeader + 8, binLength);
    }
    return Status::ok();
}

bool validIndex(const nlohmann::json& v, size_t size) {
    return v.is_number_integer() && v.get<int64_t>() >= 0 && v.get<uint64_t>() < size;
}

uint64_t unsignedField(const nlohmann::json& object, const char* key) {
    const auto& v = object.value(key, nlohmann::json(0));
    return v.is_number_integer() && v.get<int64_t>() >= 0 ? v.get<uint64_t>() : ~uint64_t(0);
}

bool validComponentType(const nlohmann::json& accessor, bool index) {
    const int64_t t = accessor.is_object() ? accessor.value("componentType", int64_t(0)) : 0;
    return t == 5121 || t == 5123 || t == 5125 || (!index && (t == 5120 || t == 5122 || t == 5126));
}

// The bufferView that holds the Draco bitstream must lie inside its buffer's declared length
// (tinygltf made the buffer's data exactly that long, or failed).
Status checkDracoView(const nlohmann::json& view, const nlohmann::json& buffers) {
    if (!view.is_object() || !validIndex(view.value("buffer", nlohmann::json()), buffers.size()))
        return Status::error("KHR_draco_mesh_compression: bufferView refers to no buffer");
    const auto& buffer = buffers[view["buffer"].get<size_t>()];
    if (!buffer.is_object()) return Status::error("KHR_draco_mesh_compression: buffer is not an object");
    const uint64_t offset = unsignedField(view, "byteOffset"), length = unsignedField(view, "byteLength");
    const uint64_t capacity = unsignedField(buffer, "byteLength");
    if (offset > capacity || length > capacity - offset)
        return Status::error("KHR_draco_mesh_compression: bufferView exceeds its buffer");
    return Status::ok();
}

// tinygltf's Draco path indexes arrays without bounds checks; refuse bad references first.
Status checkDracoPrimitive(const nlohmann::json& doc, const nlohmann::json& prim) {
    const auto& ext = prim["extensions"]["KHR_draco_mesh_compression"];
    const auto& views = doc.value("bufferViews", nlohmann::json::array());
    const auto& buffers = doc.value("buffers", nlohmann::json::array());
    const auto& accessors = doc.value("accessors", nlohmann::json::array());
    if (!ext.is_object() || !validIndex(ext.value("bufferView", nlohmann::json()), views.size()))
        return Status::error("KHR_draco_mesh_compression: bad bufferView");
    if (Status s = checkDracoView(views[ext["bufferView"].get<size_t>()], buffers); !s.isOk()) return s;
    if (prim.contains("indices") &&
        (!validIndex(prim["indices"], accessors.size()) || !validComponentType(accessors[prim["indices"].get<size_t>()], true)))
        return Status::error("KHR_draco_mesh_compression: bad indices accessor");
    const auto& attributes = ext.value("attributes", nlohmann::json());
    const auto& primAttributes = prim.value("attributes", nlohmann::json::object());
    if (!attributes.is_object() || !primAttributes.is_object())
        return Status::error("KHR_draco_mesh_compression: missing attributes");
    for (const auto& [name, id] : attributes.items()) {
        if (!id.is_number_integer() || !primAttributes.contains(name) ||
            !validIndex(primAttributes[name], accessors.size()) ||
            !validComponentType(accessors[primAttributes[name].get<size_t>()], false))
            return Status::error("KHR_draco_mesh_compression: attribute " + name + " has no valid accessor");
    }
    return Status::ok();
}

Status checkDocument(const nlohmann::json& doc) {
    VASTRAY_TRY(checkGltfTypes(doc));
    VASTRAY_TRY(checkBufferViews(doc));
    for (const auto& ext : doc.value("extensionsRequired", nlohmann::json::array())) {
        const std::string name = ext.is_string() ? ext.get<std::string>() : ext.dump();
        if (!kSupportedRequired.count(name)) return Status::error("required extension '" + name + "' is not supported");
    }
    const auto& meshes = doc.value("meshes", nlohmann::json::array());
    for (size_t m = 0; m < meshes.size(); ++m) {
        const auto& prims = meshes[m].is_object() ? meshes[m].value("primitives", nlohmann::json::array())
                                                   : nlohmann::json::array();
        for (size_t p = 0; p < prims.size(); ++p) {
            if (!prims[p].is_object() || !prims[p].contains("extensions") || !prims[p]["extensions"].is_object() ||
                !prims[p]["extensions"].contains("KHR_draco_mesh_compression"))
                continue;
            if (Status s = checkDracoPrimitive(doc, prims[p]); !s.isOk())
                return s.withContext("mesh " + std::to_string(m) + " primitive " + std::to_string(p) + ": ");
        }
    }
    return Status::ok();
}

// Sets `version1` (and stops) when asset.version is "1.x". Lists the EXT_meshopt_compression
// views in `meshopt` and leaves the document they were rewritten in (GltfMeshopt.h) in `doc`.
Status precheckJson(std::string_view text, std::string_view bin, const std::string& folder, bool& version1,
                    nlohmann::json& doc, std::vector<MeshoptView>& meshopt) {
    if (jsonDepth(text, kMaxJsonDepth) > kMaxJsonDepth)
        return Status::error("JSON nests deeper than " + std::to_string(kMaxJsonDepth) + " levels (the limit)");
    try {
        doc = nlohmann::json::parse(text.begin(), text.end());
        if ((version1 = isJsonVersion1(doc))) return Status::ok();
        if (Status s = checkDocument(doc); !s.isOk()) return s;
        if (Status s = checkDracoAttributes(doc, bin, folder); !s.isOk()) return s;
        return prepareMeshopt(doc, meshopt);
    } catch (const std::exception& e) {
        return Status::error(std::string("JSON: ") + e.what());
    }
}

// A GLB whose JSON chunk is `json` and whose BIN chunk is `bin` (4-byte aligned chunks).
std::vector<char> rebuildGlb(const std::string& json, std::string_view bin) {
    auto pad = [](size_t n) { return (n + 3) & ~size_t(3); };
    const size_t jsonLength = pad(json.size()), binLength = pad(bin.size());
    const size_t total = 12 + 8 + jsonLength + (bin.empty() ? 0 : 8 + binLength);
    std::vector<char> out;
    out.reserve(total);
    auto u32 = [&](uint32_t v) { out.insert(out.end(), reinterpret_cast<char*>(&v), reinterpret_cast<char*>(&v) + 4); };
    out.insert(out.end(), {'g', 'l', 'T', 'F'});
    u32(2);
    u32(uint32_t(total));
    u32(uint32_t(jsonLength));
    u32(0x4E4F534Au);
    out.insert(out.end(), json.begin(), json.end());
    out.resize(20 + jsonLength, ' ');
    if (!bin.empty()) {
        u32(uint32_t(binLength));
        u32(0x004E4942u);
        out.insert(out.end(), bin.begin(), bin.end());
        out.resize(total, 0);
    }
    return out;
}

}  // namespace

Result<tinygltf::Model> loadGltfModel(const std::string& path, bool binary, bool* version1) {
    const std::string name = fileNameOf(path);
    auto bytes = readWholeFile(path);
    if (!bytes) return bytes.status();
    bool isVersion1 = binary && isGlbVersion1(*bytes);
    if (bytes->size() > std::numeric_limits<unsigned>::max())  // tinygltf takes 32-bit lengths
        return errorIn(name, "file of " + std::to_string(bytes->size()) + " bytes exceeds the 4 GiB glTF limit");
    std::string_view json(bytes->data(), bytes->size()), bin;
    std::vector<MeshoptView> meshopt;
    if (!isVersion1) {
        if (binary)
            if (Status s = checkGlbHeader(*bytes, json, bin); !s.isOk()) return s.withContext(name + ": ");
        nlohmann::json doc;
        if (Status s = precheckJson(json, bin, directoryOf(path), isVersion1, doc, meshopt); !s.isOk())
            return s.withContext(name + ": ");
        if (!meshopt.empty()) {  // tinygltf parses the rewritten document
            std::string text = doc.dump();
            *bytes = binary ? rebuildGlb(text, bin) : std::vector<char>(text.begin(), text.end());
        }
    }
    if (isVersion1) {
        if (version1) *version1 = true;
        return errorIn(name, "glTF 1.0; this importer reads glTF 2.0");
    }

    Sandbox box{directoryOf(path), {}};
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks({&sandboxFileExists, &sandboxExpand, &sandboxRead, &sandboxWrite, &box});
    loader.SetImageLoader(&keepEncodedImage, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    bool ok = false;
    try {
        const auto* data = reinterpret_cast<const unsigned char*>(bytes->data());
        ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, unsigned(bytes->size()), box.folder)
                    : loader.LoadASCIIFromString(&model, &err, &warn, bytes->data(), unsigned(bytes->size()),
                                                 box.folder);
    } catch (const std::exception& e) {
        return errorIn(name, std::string("glTF parse error: ") + e.what());
    }
    if (!box.violation.empty()) return errorIn(name, box.violation);
    if (!ok) {
        while (!err.empty() && err.back() == '\n') err.pop_back();
        return errorIn(name, err.empty() ? "glTF load failed" : err);
    }
    if (Status s = decodeMeshopt(model, meshopt); !s.isOk()) return s.withContext(name + ": ");
    return model;
}

}  // namespace vastray::import

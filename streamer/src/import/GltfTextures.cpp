#include "import/GltfTextures.h"

#include <filesystem>

#include <cmath>
#include <map>
#include <tuple>

#include "import/DataUri.h"
#include "import/ImportCommon.h"
#include "vastray/core/ImageFile.h"

namespace vastray::import {
namespace {

Result<TextureWrap> wrapMode(int mode) {
    switch (mode) {
        case 10497: return TextureWrap::Repeat;
        case 33071: return TextureWrap::Clamp;
        case 33648: return TextureWrap::Mirror;
    }
    return Status::error("wrap mode " + std::to_string(mode) + " is not 10497, 33071 or 33648");
}

// KHR_texture_transform of a textureInfo, or the identity.
Result<UvTransform> transformOf(const tinygltf::ExtensionMap& extensions) {
    const auto it = extensions.find("KHR_texture_transform");
    if (it == extensions.end()) return kIdentityUvTransform;
    const tinygltf::Value& t = it->second;
    float offset[2] = {0.0f, 0.0f}, scale[2] = {1.0f, 1.0f}, rotation = 0.0f;
    auto pair = [&](const char* key, float* out) -> Status {
        if (!t.Has(key)) return Status::ok();
        const tinygltf::Value& v = t.Get(key);
        if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
            return Status::error(std::string("KHR_texture_transform ") + key + " is not an array of two numbers");
        for (int i = 0; i < 2; ++i) out[i] = float(v.Get(i).GetNumberAsDouble());
        return Status::ok();
    };
    VASTRAY_TRY(pair("offset", offset));
    VASTRAY_TRY(pair("scale", scale));
    if (t.Has("rotation")) {
        if (!t.Get("rotation").IsNumber()) return Status::error("KHR_texture_transform rotation is not a number");
        rotation = float(t.Get("rotation").GetNumberAsDouble());
    }
    for (float v : {offset[0], offset[1], scale[0], scale[1], rotation})
        if (!std::isfinite(v) || std::fabs(v) > kMaxUvTransformValue)
            return Status::error("KHR_texture_transform value " + std::to_string(v) + " is outside +-" +
                                 std::to_string(kMaxUvTransformValue));
    return khrTextureTransform(offset[0], offset[1], rotation, scale[0], scale[1]);
}

std::string imageName(const tinygltf::Model& model, int image, const std::string& fileName) {
    const tinygltf::Image& i = model.images[size_t(image)];
    std::string label = !i.name.empty() ? i.name : (!i.uri.empty() && i.uri.rfind("data:", 0) != 0 ? i.uri : "");
    return "image " + std::to_string(image) + (label.empty() ? "" : " ('" + label + "')") + " of " + fileName;
}

// "%20" -> " ": glTF URIs are URI-encoded (RFC 3986); a malformed escape stays as it is.
std::string percentDecoded(const std::string& uri) {
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) &&
            std::isxdigit(uint8_t(uri[i + 2]))) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// A textureInfo object of an extension (a tinygltf::Value): its index, texCoord and extensions.
GltfMapInfo extensionMap(TextureSlot slot, const tinygltf::Value& info) {
    GltfMapInfo map;
    map.slot = slot;
    if (!info.IsObject() || !info.Has("index") || !info.Get("index").IsInt()) return map;
    map.index = info.Get("index").GetNumberAsInt();
    if (info.Has("texCoord") && info.Get("texCoord").IsInt()) map.texCoord = info.Get("texCoord").GetNumberAsInt();
    if (info.Has("extensions") && info.Get("extensions").IsObject()) {
        const tinygltf::Value& extensions = info.Get("extensions");
        for (const std::string& key : extensions.Keys()) map.extensions[key] = extensions.Get(key);
    }
    return map;
}

class Reader {
public:
    Reader(const tinygltf::Model& model, const std::string& fileName, const std::string& folder,
           ImportReport& report)
        : model_(model), fileName_(fileName), folder_(folder), report_(report) {}

    Result<GltfTextures> read() {
        for (size_t m = 0; m < model_.materials.size(); ++m) {
            const tinygltf::Material& g = model_.materials[m];
            const std::string where =
                "material " + std::to_string(m) + (g.name.empty() ? "" : " ('" + g.name + "')") + " ";
            MaterialTextures t;
            for (const GltfMapInfo& map : gltfMaterialMaps(g)) {
                if (map.index < 0) continue;
                const std::string at = where + textureSlotName(map.slot) + ": ";
                auto binding = bind(map.index, map.slot, map.extensions);
                if (!binding) return binding.status().withContext(fileName_ + ": " + at);
                t.slots[uint32_t(map.slot)] = *binding;
            }
            t.normalScale = float(g.normalTexture.scale);
            t.occlusionStrength = float(g.occlusionTexture.strength);
            if (!std::isfinite(t.normalScale) || std::fabs(t.normalScale) > kMaxUvTransformValue)
                return Status::error(fileName_ + ": " + where + "normalTexture scale " +
                                     std::to_string(g.normalTexture.scale) + " is not finite within +-1e6");
            if (!(t.occlusionStrength >= 0.0f && t.occlusionStrength <= 1.0f))
                return Status::error(fileName_ + ": " + where + "occlusionTexture strength " +
                                     std::to_string(g.occlusionTexture.strength) + " is outside [0, 1]");
            out_.materials.push_back(t);
        }
        report_.warnUnused("texture maps whose image file is missing or unreadable", missing_,
                           "their maps are rendered without them");
        for (const auto& [format, count] : unreadableKtx2_)
            report_.warnUnused("texture maps with a KTX2 image in " + format, count,
                               "a format not read here; their maps are rendered without them");
        report_.warnUnused("texture maps whose KTX2 image's transfer function is not the map's (sRGB for base colour "
                           "and emissive, linear for the others)",
                           ktx2TransferMismatch_, "their texels are read as the map's, as glTF says");
        report_.warnUnused("texture maps with an image neither PNG, JPEG nor KTX2", unknown_,
                           "their maps are rendered without them");
        report_.warnUnused("texture maps whose image only an extension names (EXT_texture_webp, EXT_texture_avif, ...)",
                           extensionOnly_, "their maps are rendered without them");
        return std::move(out_);
    }

private:
    // The binding of one map: kNoTexture (warned) when its image cannot be read here.
    Result<TextureBinding> bind(int index, TextureSlot slot, const tinygltf::ExtensionMap& extensions) {
        if (size_t(index) >= model_.textures.size())
            return Status::error("texture " + std::to_string(index) + " does not exist (the file has " +
                                 std::to_string(model_.textures.size()) + ")");
        const tinygltf::Texture& texture = model_.textures[size_t(index)];
        TextureBinding binding;
        auto transform = transformOf(extensions);
        if (!transform) return transform.status();
        binding.transform = *transform;
        auto basisSource = basisuSource(texture);
        if (!basisSource) return basisSource.status().withContext("texture " + std::to_string(index) + " ");
        if (texture.source < 0 && *basisSource < 0) {
            ++extensionOnly_;
            return binding;
        }
        for (int source : {*basisSource, texture.source})
            if (source >= 0 && size_t(source) >= model_.images.size())
                return Status::error("texture " + std::to_string(index) + "'s image " + std::to_string(source) +
                                     " does not exist (the file has " + std::to_string(model_.images.size()) + ")");
        TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
        if (texture.sampler >= 0) {
            if (size_t(texture.sampler) >= model_.samplers.size())
                return Status::error("texture " + std::to_string(index) + "'s sampler " +
                                     std::to_string(texture.sampler) + " does not exist");
            const tinygltf::Sampler& sampler = model_.samplers[size_t(texture.sampler)];
            auto s = wrapMode(sampler.wrapS), t = wrapMode(sampler.wrapT);
            if (!s) return s.status().withContext("sampler " + std::to_string(texture.sampler) + " wrapS: ");
            if (!t) return t.status().withContext("sampler " + std::to_string(texture.sampler) + " wrapT: ");
            wrapS = *s;
            wrapT = *t;
        }
        auto picked = pickImage(*basisSource, texture.source, slot);
        if (!picked) return picked.status();
        if (picked->image < 0) return binding;
        const auto key = std::make_tuple(picked->image, wrapS, wrapT, slotEncoding(slot));
        auto found = textureOf_.find(key);
        if (found == textureOf_.end()) {
            if (out_.textures.size() >= kMaxSceneTextures)
                return Status::error("more than " + std::to_string(kMaxSceneTextures) +
                                     " textures (image, sampler and encoding) in one scene");
            TextureSource source;
            source.name = imageName(model_, picked->image, fileName_);
            source.extension = picked->extension;
            source.bytes = std::move(picked->bytes);
            source.wrapS = wrapS;
            source.wrapT = wrapT;
            source.encoding = slotEncoding(slot);
            found = textureOf_.emplace(key, uint32_t(out_.textures.size())).first;
            out_.textures.push_back(std::move(source));
        }
        binding.texture = found->second;
        return binding;
    }

    // KHR_texture_basisu's source (a KTX2 image), or -1 when the texture has no such extension.
    static Result<int> basisuSource(const tinygltf::Texture& texture) {
        const auto it = texture.extensions.find("KHR_texture_basisu");
        if (it == texture.extensions.end()) return -1;
        const tinygltf::Value& source = it->second.Get("source");
        if (!source.IsInt() || source.GetNumberAsInt() < 0)
            return Status::error("KHR_texture_basisu source is not an image index");
        return source.GetNumberAsInt();
    }

    struct PickedImage {
        int image = -1;  // -1: none read here (counted in a warning)
        std::string extension;
        std::vector<uint8_t> bytes;
    };

    // The image a map reads: KHR_texture_basisu's KTX2 where its format is read here, else the
    // texture's own source (glTF's fallback for readers without the extension). picked.image is
    // -1 when neither is read here, counted once by why.
    Result<PickedImage> pickImage(int basisSource, int source, TextureSlot slot) {
        uint64_t* unread = nullptr;
        if (basisSource >= 0) {
            auto picked = readImage(basisSource, slot, unread);
            if (!picked || picked->image >= 0 || source < 0) {
                if (picked && unread) ++*unread;
                return picked;
            }
        }
        auto picked = readImage(source, slot, unread);
        if (picked && unread) ++*unread;
        return picked;
    }

    // Image `index` if it is read here; else picked.image -1 and `unread` the counter of why.
    Result<PickedImage> readImage(int index, TextureSlot slot, uint64_t*& unread) {
        PickedImage picked;
        auto bytes = imageBytes(index);
        if (!bytes) return bytes.status();
        unread = bytes->empty() ? &missing_ : nullptr;
        picked.extension = bytes->empty() ? "" : imageSignatureExtension(*bytes);
        if (!unread && picked.extension.empty()) unread = &unknown_;
        if (!unread && picked.extension == ".ktx2") {
            auto ktx2 = describeKtx2Image(imageName(model_, index, fileName_), *bytes);
            if (!ktx2) return ktx2.status();
            if (!ktx2->readable) unread = &unreadableKtx2_[ktx2->format];
            else if (ktx2->srgb != (slotEncoding(slot) == TextureEncoding::Srgb)) ++ktx2TransferMismatch_;
        }
        if (unread) return picked;
        picked.image = index;
        picked.bytes = std::move(*bytes);
        return picked;
    }

    // The image's bytes: as the loader kept them, from a data URI of a media type the loader does
    // not decode ("data:image/ktx2;base64,..."), or its file's (empty when that is missing).
    Result<std::vector<uint8_t>> imageBytes(int index) {
        const tinygltf::Image& image = model_.images[size_t(index)];
        if (!image.image.empty() || image.uri.empty()) return image.image;
        if (image.uri.rfind("data:", 0) == 0) return base64DataUriBytes(image.uri);
        const std::string uri = percentDecoded(image.uri);
        std::string why;
        if (!isSafeRelativeUri(uri, why)) return Status::error("image " + std::to_string(index) + " uri '" + uri + "' " + why);
        const std::filesystem::path file = std::filesystem::path(folder_) / uri;
        if (!insideFolder(folder_, file))
            return Status::error("image " + std::to_string(index) + " uri '" + uri + "' leads outside the model's folder");
        auto bytes = readWholeFile(file.string());
        if (!bytes) return std::vector<uint8_t>();
        return std::vector<uint8_t>(bytes->begin(), bytes->end());
    }

    const tinygltf::Model& model_;
    const std::string& fileName_;
    const std::string& folder_;
    ImportReport& report_;
    GltfTextures out_;
    std::map<std::tuple<int, TextureWrap, TextureWrap, TextureEncoding>, uint32_t> textureOf_;
    uint64_t missing_ = 0, unknown_ = 0, extensionOnly_ = 0, ktx2TransferMismatch_ = 0;
    std::map<std::string, uint64_t> unreadableKtx2_;  // by format ("vkFormat 131 (...)")
};

}  // namespace

std::vector<GltfMapInfo> gltfMaterialMaps(const tinygltf::Material& g) {
    const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    std::vector<GltfMapInfo> maps{
        {TextureSlot::BaseColor, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
         pbr.baseColorTexture.extensions},
        {TextureSlot::MetallicRoughness, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
         pbr.metallicRoughnessTexture.extensions},
        {TextureSlot::Normal, g.normalTexture.index, g.normalTexture.texCoord, g.normalTexture.extensions},
        {TextureSlot::Emissive, g.emissiveTexture.index, g.emissiveTexture.texCoord, g.emissiveTexture.extensions},
        {TextureSlot::Occlusion, g.occlusionTexture.index, g.occlusionTexture.texCoord, g.occlusionTexture.extensions}};
    const auto coat = g.extensions.find("KHR_materials_clearcoat");
    for (auto [slot, name] : {std::pair{TextureSlot::Clearcoat, "clearcoatTexture"},
                              {TextureSlot::ClearcoatRoughness, "clearcoatRoughnessTexture"}})
        if (coat != g.extensions.end() && coat->second.Has(name)) maps.push_back(extensionMap(slot, coat->second.Get(name)));
    return maps;
}

Result<GltfTextures> readGltfTextures(const tinygltf::Model& model, const std::string& fileName,
                                      const std::string& folder, ImportReport& report) {
    return Reader(model, fileName, folder, report).read();
}

}  // namespace vastray::import

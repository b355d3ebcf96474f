// Wavefront OBJ: v (with optional r g b colour)/vt/vn/f, negative indices, ear-clipped polygons,
// usemtl/mtllib. The whole file is read once and parsed in place with std::from_chars. Normals
// and texture coordinates are indexed apart from positions: a position used with several
// normals or UVs becomes several vertices (splitVertices), as every renderer's vertex arrays
// want. UVs are kept only when the MTL library has a texture map (ImportReport::textureMaps);
// map_Kd, norm and map_Ke become the materials' maps (MtlLibrary.h, TextureFiles.h), map_d a
// cut-out's mask (AlphaMask.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include "import/AlphaMask.h"
#include "import/ImportCommon.h"
#include "import/MtlLibrary.h"
#include "import/TextScan.h"
#include "import/TextureFiles.h"
#include "import/Triangulate.h"
#include "vastray/core/VertexAttributes.h"
#include "vastray/streamer/Import.h"

namespace vastray {
namespace {

using import::parseNumber;

class ObjParser {
public:
    ObjParser(std::string path, ImportedMesh& out)
        : path_(std::move(path)), name_(import::fileNameOf(path_)), out_(out) {}

    Status parse(const char* p, const char* end) {
        for (line_ = 1; p < end; ++line_) {
            const char* eol = static_cast<const char*>(std::memchr(p, '\n', end - p));
            if (!eol) eol = end;
            if (Status s = parseLine(p, eol); !s.isOk()) return s;
            p = eol + (eol < end ? 1 : 0);
        }
        return applyMaterialLibraries();
    }

    const std::string& name() const { return name_; }
    uint64_t normalCount() const { return normals_.size(); }
    uint64_t texcoordCount() const { return texcoords_.size(); }
    uint64_t colourCount() const { return colouredVertices_; }

    // Gives the mesh its per-vertex normals, colours and (with a texture map) UVs: each
    // (position, normal, texcoord) that a face corner uses becomes one vertex; corners without
    // a normal get kNoNormal, without a texcoord (0, 0).
    void splitVertices();

private:
    Status lineError(const std::string& message) const {
        return import::errorIn(name_, "line " + std::to_string(line_) + ": " + message);
    }

    Status parseLine(const char* p, const char* eol) {
        const std::string_view keyword = import::nextToken(p, eol);
        if (keyword == "v") return parseVertex(p, eol);
        if (keyword == "vt") return parseTexcoord(p, eol);
        if (keyword == "vn") return parseNormal(p, eol);
        if (keyword == "f") return parseFace(p, eol);
        if (keyword == "usemtl") return useMaterial(std::string(import::trimmed(p, eol)));
        if (keyword == "mtllib") libraries_.emplace_back(import::trimmed(p, eol));
        return Status::ok();  // comments, o, g, s, l, p and unknown statements
    }

    Status parseVertex(const char* p, const char* eol) {
        Vec3f v;
        if (!import::parseField(p, eol, v.x) || !import::parseField(p, eol, v.y) || !import::parseField(p, eol, v.z))
            return lineError("malformed vertex position");
        if (out_.mesh.positions.size() >= std::numeric_limits<uint32_t>::max())
            return lineError("vertex count exceeds the uint32 index range");
        // "v x y z r g b" (MeshLab and scanners): colour channels in [0, 1], taken as sRGB-encoded;
        // "v x y z w": a weight, ignored.
        float rgb[4];
        int extra = 0;
        while (extra < 4 && import::parseField(p, eol, rgb[extra])) ++extra;
        if (extra == 2 || extra == 4)
            return lineError("vertex has " + std::to_string(3 + extra) + " values (expected 3, 4 with a weight, or 6 with a colour)");
        if (extra == 3) {
            auto byte = [](float c) { return uint8_t(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f)); };
            if (colours_.empty()) colours_.assign(out_.mesh.positions.size(), kWhiteColor);
            colours_.push_back(packSrgb8(byte(rgb[0]), byte(rgb[1]), byte(rgb[2])));
            ++colouredVertices_;
        } else if (!colours_.empty()) {
            colours_.push_back(kWhiteColor);
        }
        out_.mesh.positions.push_back(v);
        return Status::ok();
    }

    Status parseNormal(const char* p, const char* eol) {
        Vec3f n;
        if (!import::parseField(p, eol, n.x) || !import::parseField(p, eol, n.y) || !import::parseField(p, eol, n.z))
            return lineError("malformed vn");
        if (normals_.size() >= std::numeric_limits<uint32_t>::max() - 1)
            return lineError("normal count exceeds the uint32 index range");
        normals_.push_back(encodeOctahedral(n));
        return Status::ok();
    }

    // "vt u [v [w]]": w is dropped, a missing v is 0. Stored with v flipped (1 - v): the
    // package keeps glTF's texture space, v growing downwards (docs/RENDERING.md).
    Status parseTexcoord(const char* p, const char* eol) {
        float u = 0.0f, v = 0.0f;
        if (!import::parseField(p, eol, u)) return lineError("malformed vt");
        const bool hasV = import::parseField(p, eol, v);
        if (texcoords_.size() >= std::numeric_limits<uint32_t>::max() - 1)
            return lineError("texcoord count exceeds the uint32 index range");
        if (const std::string problem = import::uvProblem(u, v); !problem.empty()) return lineError("vt " + problem);
        texcoords_.push_back({u, hasV ? 1.0f - v : 1.0f});
        return Status::ok();
    }

    // OBJ indices are 1-based; negative ones count back from the last element defined so far.
    Status resolve(int64_t index, uint64_t defined, const char* what, uint32_t& out) const {
        const int64_t resolved = index > 0 ? index - 1 : static_cast<int64_t>(defined) + index;
        if (index == 0 || resolved < 0 || static_cast<uint64_t>(resolved) >= defined)
            return lineError(std::string(what) + " index " + std::to_string(index) +
                             " is out of range (" + std::to_string(defined) + " defined so far)");
        out = static_cast<uint32_t>(resolved);
        return Status::ok();
    }

    Status parseCorner(std::string_view token, uint32_t& vertex, uint32_t& texcoord, uint32_t& normal) const {
        const char* p = token.data();
        const char* end = p + token.size();
        int64_t index = 0;
        if (!parseNumber(p, end, index)) return lineError("malformed face corner '" + std::string(token) + "'");
        if (Status s = resolve(index, out_.mesh.positions.size(), "vertex", vertex); !s.isOk()) return s;
        const uint64_t counts[2] = {texcoords_.size(), normals_.size()};
        const char* names[2] = {"texcoord", "normal"};
        normal = texcoord = kNoCorner;
        for (int slot = 0; slot < 2 && p < end; ++slot) {
            if (*p != '/') return lineError("malformed face corner '" + std::string(token) + "'");
            ++p;
            if (p < end && *p == '/') continue;  // v//vn: no texcoord
            uint32_t resolved;
            if (!parseNumber(p, end, index)) return lineError("malformed face corner '" + std::string(token) + "'");
            if (Status s = resolve(index, counts[slot], names[slot], resolved); !s.isOk()) return s;
            (slot == 1 ? normal : texcoord) = resolved;
        }
        if (p != end) return lineError("malformed face corner '" + std::string(token) + "'");
        return Status::ok();
    }

    Status parseFace(const char* p, const char* eol) {
        corners_.clear();
        cornerNormals_.clear();
        cornerTexcoords_.clear();
        bool anyNormal = false, anyTexcoord = false;
        for (std::string_view token = import::nextToken(p, eol); !token.empty();
             token = import::nextToken(p, eol)) {
            uint32_t vertex = 0, texcoord = kNoCorner, normal = kNoCorner;
            if (Status s = parseCorner(token, vertex, texcoord, normal); !s.isOk()) return s;
            if (corners_.size() == import::kMaxPolygonCorners)
                return lineError("face has more than " + std::to_string(import::kMaxPolygonCorners) +
                                 " corners (the polygon limit)");
            corners_.push_back(vertex);
            cornerNormals_.push_back(normal);
            cornerTexcoords_.push_back(texcoord);
            anyNormal = anyNormal || normal != kNoCorner;
            anyTexcoord = anyTexcoord || texcoord != kNoCorner;
        }
        if (corners_.size() < 3)
            return lineError("face has " + std::to_string(corners_.size()) + " vertices (need at least 3)");
        const uint32_t material = currentMaterial();
        const size_t first = out_.mesh.indices.size();
        const uint64_t triangles = triangulator_.triangulate(out_.mesh.positions, corners_, out_.mesh.indices);
        if (!triangulator_.failure().empty()) return lineError("face: " + triangulator_.failure());
        out_.mesh.materialIds.insert(out_.mesh.materialIds.end(), triangles, material);
        recordCorners(first, anyNormal, cornerNormals_, indexNormals_);
        recordCorners(first, anyTexcoord, cornerTexcoords_, indexTexcoords_);
        return Status::ok();
    }

    // The triangulator returns position indices: each new corner takes the normal (texcoord)
    // its position had in the face (the first such corner's, if a polygon repeats a position).
    // `perIndex` stays empty until some face has one.
    void recordCorners(size_t first, bool any, const std::vector<uint32_t>& perCorner, std::vector<uint32_t>& perIndex) {
        const size_t added = out_.mesh.indices.size() - first;
        if (!any) {
            if (!perIndex.empty()) perIndex.insert(perIndex.end(), added, kNoCorner);
            return;
        }
        if (perIndex.empty()) perIndex.assign(first, kNoCorner);
        // Large polygons look their corners up in a map (a 10^6-corner face stays linear).
        std::unordered_map<uint32_t, uint32_t> valueOf;
        if (corners_.size() > 16)
            for (size_t c = corners_.size(); c-- > 0;) valueOf[corners_[c]] = perCorner[c];
        for (size_t i = first; i < out_.mesh.indices.size(); ++i) {
            uint32_t value = kNoCorner;
            if (corners_.size() > 16) {
                value = valueOf[out_.mesh.indices[i]];
            } else {
                for (size_t c = 0; c < corners_.size(); ++c)
                    if (corners_[c] == out_.mesh.indices[i]) {
                        value = perCorner[c];
                        break;
                    }
            }
            perIndex.push_back(value);
        }
    }

    // A bare "usemtl" selects the default material (some exporters write it).
    Status useMaterial(std::string name) {
        current_ = materialId(name);
        return Status::ok();
    }

    uint32_t materialId(const std::string& name) {
        auto [it, inserted] = materialIds_.try_emplace(name, static_cast<uint32_t>(out_.mesh.materials.size()));
        if (inserted) out_.mesh.materials.push_back(Material{name});
        return it->second;
    }

    // Faces before any usemtl share one default material, created on first use.
    uint32_t currentMaterial() {
        if (current_ < 0) current_ = materialId("");
        return static_cast<uint32_t>(current_);
    }

    // map_d statements left out, by why.
    struct AlphaMapsLeftOut {
        uint64_t sampling = 0, depth = 0;
    };

    Status applyMaterialLibraries();
    Status bindMaps(const import::MtlEntry& entry, import::TextureFiles& files, MaterialTextures& out);
    Status addAlphaMask(uint32_t material, const import::MtlEntry& e, import::TextureFiles& files,
                        std::vector<import::AlphaMaskRequest>& masks, AlphaMapsLeftOut& leftOut);

    // "mtllib a.mtl b.mtl" names two files, but some exporters write one name with spaces.
    std::vector<std::string> libraryFiles() const {
        std::vector<std::string> files;
        for (const std::string& line : libraries_) {
            files.push_back(line);
            const char* p = line.data();
            const char* end = p + line.size();
            for (auto t = import::nextToken(p, end); !t.empty(); t = import::nextToken(p, end))
                if (t.size() != line.size()) files.emplace_back(t);
        }
        return files;
    }

    std::string path_;
    std::string name_;
    ImportedMesh& out_;
    uint64_t line_ = 0;
    static constexpr uint32_t kNoCorner = 0xFFFFFFFFu;  // a face corner without a normal or texcoord
    uint64_t colouredVertices_ = 0;
    int64_t current_ = -1;
    std::vector<uint32_t> normals_;       // octahedral codes of the vn lines
    std::vector<uint32_t> colours_;       // per v line once one has a colour (white before)
    std::vector<uint32_t> indexNormals_;  // per mesh index: its vn, once a face used one
    std::vector<std::array<float, 2>> texcoords_;  // the vt lines, v flipped
    std::vector<uint32_t> indexTexcoords_;  // per mesh index: its vt, once a face used one
    std::vector<uint32_t> corners_;  // reused for every face: no per-face allocation
    std::vector<uint32_t> cornerNormals_, cornerTexcoords_;
    import::PolygonTriangulator triangulator_;
    std::unordered_map<std::string, uint32_t> materialIds_;
    std::vector<std::string> libraries_;

};

// A library next to the model is optional: exporters often reference one they never wrote (a
// warning says so: an upload that left its .mtl behind renders grey, and the user should know).
// Like glTF URIs, names stay inside the model's folder: the service imports uploaded OBJ
// files, and a client must not make it read (and render the colours of) files elsewhere.
Status ObjParser::applyMaterialLibraries() {
    import::MtlLibrary library;
    import::MtlUnused unused;
    const std::filesystem::path folder = import::directoryOf(path_);
    for (const std::string& name : libraryFiles()) {
        std::string why;
        if (!import::isSafeRelativeUri(name, why)) return import::errorIn(name_, "mtllib '" + name + "' " + why);
        const std::filesystem::path file = folder / name;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec)) {
            out_.report.warnings.push_back("mtllib '" + name + "' is not in the model's folder: its materials stay " +
                                           "the default grey");
            continue;
        }
        if (!import::insideFolder(folder, file))
            return import::errorIn(name_, "mtllib '" + name + "' resolves outside the model folder (a link)");
        if (Status s = import::parseMtlFile(file.string(), name, library, unused); !s.isOk()) return s;
    }
    out_.report.textureMaps = unused.maps;
    for (const auto& [kind, counted] : unused.kinds) out_.report.warnUnused("MTL " + kind, counted.first, counted.second);
    import::TextureFiles files(folder, name_);
    std::vector<import::AlphaMaskRequest> masks;
    AlphaMapsLeftOut leftOut;
    for (uint32_t i = 0; i < out_.mesh.materials.size(); ++i) {
        Material& m = out_.mesh.materials[i];
        if (m.name.empty()) m.name = "default";
        const auto it = library.find(m.name);
        if (it == library.end()) continue;
        const import::MtlEntry& e = it->second;
        // d below 1 (or Tr above 0) blends: the surface is there with that probability.
        m.baseColor = {e.diffuse[0], e.diffuse[1], e.diffuse[2], e.opacity};
        m.alphaBlend = e.opacity < 1.0f;
        m.emissive = e.emissive;
        // Ks and Ns: a dielectric specular layer (illum 0 and 1 have no highlight).
        if (e.illumination >= 2) import::setPhongSpecular(m, std::max({e.specular[0], e.specular[1], e.specular[2]}), e.exponent);
        Status s = bindMaps(e, files, m.textures);
        if (s.isOk()) s = addAlphaMask(i, e, files, masks, leftOut);
        if (!s.isOk()) return import::errorIn(import::fileNameOf(e.library), "material '" + m.name + "' " + s.message());
    }
    out_.report.warnUnused("MTL alpha maps (map_d) with other -s, -o or -clamp than map_Kd", leftOut.sampling,
                           "rendered opaque: a mask is baked into map_Kd's alpha texel for texel");
    out_.report.warnUnused("MTL alpha maps (map_d) of channel -imfchan z (depth)", leftOut.depth,
                           "rendered opaque: PNG and JPEG images have no depth channel");
    files.warn(out_.report);
    out_.mesh.textures = std::move(files.textures());
    return import::bakeAlphaMasks(out_.mesh, masks).withContext(name_ + ": ");
}

// An MTL map's -s and -o in the package's texture space. MTL maps v up (OBJ's vt): u' = s_u u +
// o_u, v' = s_v v + o_v. The package stores g = 1 - v (glTF's v down) and samples the image at
// g' = 1 - v' = 1 - s_v (1 - g) - o_v = s_v g + (1 - s_v - o_v).
UvTransform mtlUvTransform(const import::MtlMap& map) {
    return import::vUpToVDown({map.scale[0], 0.0f, map.offset[0], 0.0f, map.scale[1], map.offset[1]});
}

// The binding of `map` (its file relative to the library's folder), kNoTexture when its image is
// missing or not PNG/JPEG (counted by `files`, warned).
Result<TextureBinding> bindMap(const import::MtlMap& map, const std::string& library, import::TextureFiles& files,
                               TextureEncoding encoding) {
    const std::filesystem::path libraryFolder = std::filesystem::path(library).parent_path();
    const TextureWrap wrap = map.clamp ? TextureWrap::Clamp : TextureWrap::Repeat;
    std::string why;
    if (!import::isSafeRelativeUri(map.file, why))
        return Status::error("line " + std::to_string(map.line) + ": image '" + map.file + "' " + why);
    auto texture = files.addFile((libraryFolder / map.file).generic_string(), wrap, wrap, encoding);
    if (!texture) return texture.status().withContext("line " + std::to_string(map.line) + ": ");
    return TextureBinding{*texture, mtlUvTransform(map)};
}

// The material's map_Kd, norm and map_Ke, each a texture of `files`.
Status ObjParser::bindMaps(const import::MtlEntry& entry, import::TextureFiles& files, MaterialTextures& out) {
    for (uint32_t slot = 0; slot < kTextureSlotCount; ++slot) {
        if (entry.maps[slot].file.empty()) continue;
        auto binding = bindMap(entry.maps[slot], entry.library, files, slotEncoding(TextureSlot(slot)));
        if (!binding) return binding.status();
        out.slots[slot] = *binding;
    }
    return Status::ok();
}

// -imfchan's letter as a mask channel (z, depth, is left out before).
import::MaskChannel maskChannel(char imfchan) {
    switch (imfchan) {
        case 'r': return import::MaskChannel::Red;
        case 'g': return import::MaskChannel::Green;
        case 'b': return import::MaskChannel::Blue;
        case 'm': return import::MaskChannel::Alpha;
        case 'l': return import::MaskChannel::Luminance;
        default: return import::MaskChannel::Auto;
    }
}

// One image name as TextureFiles keys it: '\' read as '/', lexically normal.
std::string imageKey(const std::string& file) {
    std::string name = file;
    std::replace(name.begin(), name.end(), '\\', '/');
    return std::filesystem::path(name).lexically_normal().generic_string();
}

// map_d: the mask of a cut-out (docs/RENDERING.md, "Cut-outs"), baked into map_Kd's alpha by
// bakeAlphaMasks (map_Kd's own image and its alpha: no baking). With a map_Kd the mask must share
// its -s, -o and -clamp (it is baked texel for texel); without one (or with its image missing)
// the mask goes on white with its own options. A missing or unknown mask image is counted by
// `files` (warned) and left out.
Status ObjParser::addAlphaMask(uint32_t material, const import::MtlEntry& e, import::TextureFiles& files,
                               std::vector<import::AlphaMaskRequest>& masks, AlphaMapsLeftOut& leftOut) {
    const import::MtlMap &alpha = e.alphaMap, &base = e.maps[uint32_t(TextureSlot::BaseColor)];
    if (alpha.file.empty()) return Status::ok();
    if (alpha.channel == 'z') return ++leftOut.depth, Status::ok();
    const bool hasBase =
        out_.mesh.materials[material].textures.slots[uint32_t(TextureSlot::BaseColor)].texture != kNoTexture;
    if (hasBase && (alpha.scale != base.scale || alpha.offset != base.offset || alpha.clamp != base.clamp))
        return ++leftOut.sampling, Status::ok();
    auto mask = bindMap(alpha, e.library, files, TextureEncoding::Linear);
    if (!mask) return mask.status();
    if (mask->texture == kNoTexture) return Status::ok();
    masks.push_back({material, mask->texture, maskChannel(alpha.channel), mask->transform,
                     hasBase && imageKey(alpha.file) == imageKey(base.file)});
    return Status::ok();
}

void ObjParser::splitVertices() {
    TriangleMesh& mesh = out_.mesh;
    // UVs nothing reads (no texture map) would only split vertices: left out.
    if (out_.report.textureMaps == 0) indexTexcoords_.clear();
    if (indexNormals_.empty() && indexTexcoords_.empty()) {
        mesh.colors = std::move(colours_);
        return;
    }
    // Key: position and normal in 64 bits, then the texcoord (kNoCorner where a face had none).
    struct Key {
        uint64_t positionNormal;
        uint32_t texcoord;
        bool operator==(const Key&) const = default;
    };
    struct KeyHash {
        size_t operator()(const Key& k) const { return std::hash<uint64_t>()(k.positionNormal ^ (uint64_t(k.texcoord) * 0x9E3779B97F4A7C15ull)); }
    };
    std::unordered_map<Key, uint32_t, KeyHash> vertexOf;
    std::vector<Vec3f> positions;
    std::vector<uint32_t> normals, colours;
    std::vector<std::array<float, 2>> uvs;
    for (size_t i = 0; i < mesh.indices.size(); ++i) {
        const uint32_t position = mesh.indices[i];
        const uint32_t normal = indexNormals_.empty() ? kNoCorner : indexNormals_[i];
        const uint32_t texcoord = indexTexcoords_.empty() ? kNoCorner : indexTexcoords_[i];
        const auto [it, added] =
            vertexOf.try_emplace(Key{(uint64_t(position) << 32) | normal, texcoord}, uint32_t(positions.size()));
        if (added) {
            positions.push_back(mesh.positions[position]);
            if (!indexNormals_.empty()) normals.push_back(normal == kNoCorner ? kNoNormal : normals_[normal]);
            if (!colours_.empty()) colours.push_back(colours_[position]);
            if (!indexTexcoords_.empty())
                uvs.push_back(texcoord == kNoCorner ? std::array<float, 2>{0.0f, 0.0f} : texcoords_[texcoord]);
        }
        mesh.indices[i] = it->second;
    }
    mesh.positions = std::move(positions);
    mesh.normals = std::move(normals);
    mesh.colors = std::move(colours);
    mesh.uvs = std::move(uvs);
}

Result<ImportedMesh> importObjUnguarded(const std::string& path, const ImportOptions& options) {
    auto bytes = import::readWholeFile(path);
    if (!bytes) return bytes.status();
    ImportedMesh imported;
    imported.report.format = "obj";
    ObjParser parser(path, imported);
    const char* data = bytes->data();
    if (Status s = parser.parse(data, data + bytes->size()); !s.isOk()) return s;
    imported.report.verticesRead = imported.mesh.positions.size();
    imported.report.normalsRead = parser.normalCount();
    imported.report.coloursRead = parser.colourCount();
    imported.report.texcoordsRead = parser.texcoordCount();
    parser.splitVertices();
    if (Status s = finalizeMesh(parser.name(), options, imported); !s.isOk()) return s;
    return imported;
}

}  // namespace

Result<ImportedMesh> importObj(const std::string& path, const ImportOptions& options) {
    return import::guarded(path, [&]() -> Result<ImportedMesh> { return importObjUnguarded(path, options); });
}

}  // namespace vastray

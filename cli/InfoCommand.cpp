#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "CellExport.h"
#include "Commands.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/VolumeLeaf.h"
#include "vastray/core/PathShading.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray::cli {
namespace {

nlohmann::json boundsJson(const Aabb& b) {
    return {{"min", {b.lo.x, b.lo.y, b.lo.z}}, {"max", {b.hi.x, b.hi.y, b.hi.z}}};
}

// The compressed bytes of a texture's pages in the package.
uint64_t textureStoredBytes(const PackageInfo& info, uint32_t texture) {
    const PackageTexture& x = info.textures[texture];
    uint64_t bytes = 0;
    for (uint32_t p = 0; p < x.layout.pageCount; ++p) bytes += info.texturePages[x.firstEntry + p].size;
    return bytes;
}

nlohmann::json infoJson(const PackageInfo& info) {
    nlohmann::json chunks = nlohmann::json::array();
    for (const ChunkInfo& c : info.chunks)
        chunks.push_back({{"id", c.id},
                          {"offset", c.offset},
                          {"size", c.size},
                          {"triangles", c.triangleCount},
                          {"vertices", c.vertexCount},
                          {"bvh_nodes", c.bvhNodeCount},
                          {"resident_bytes", c.residentBytes},
                          {"checksum", c.checksum},
                          {"bounds", boundsJson(c.cell)}});
    nlohmann::json materials = nlohmann::json::array();
    for (const Material& m : info.materials) {
        nlohmann::json maps = nlohmann::json::object();
        for (uint32_t s = 0; s < kTextureSlotCount; ++s) {
            const TextureBinding& b = m.textures.slots[s];
            if (b.texture == kNoTexture) continue;
            maps[textureSlotName(TextureSlot(s))] = {{"texture", b.texture}, {"uv_transform", b.transform}};
        }
        materials.push_back({{"name", m.name},
                             {"base_color", m.baseColor},
                             {"emissive", m.emissive},
                             {"metallic", m.metallic},
                             {"roughness", m.roughness},
                             {"specular", m.specular},
                             {"specular_color", m.specularColor},
                             {"clearcoat", m.clearcoat},
                             {"clearcoat_roughness", m.clearcoatRoughness},
                             {"ior", m.ior},
                             {"double_sided", m.doubleSided},
                             {"alpha_cutoff", m.alphaCutoff},
                             {"alpha_blend", m.alphaBlend},
                             {"maps", maps},
                             {"normal_scale", m.textures.normalScale},
                             {"occlusion_strength", m.textures.occlusionStrength}});
    }
    nlohmann::json textures = nlohmann::json::array();
    for (uint32_t t = 0; t < info.textures.size(); ++t) {
        const PackageTexture& x = info.textures[t];
        textures.push_back({{"name", x.name},
                            {"width", x.layout.width},
                            {"height", x.layout.height},
                            {"levels", x.layout.levelCount},
                            {"pages", x.layout.pageCount},
                            {"stored_bytes", textureStoredBytes(info, t)},
                            {"wrap", {textureWrapName(x.wrapS), textureWrapName(x.wrapT)}},
                            {"encoding", x.encoding == TextureEncoding::Srgb ? "srgb" : "linear"}});
    }
    nlohmann::json volumes = nlohmann::json::array();
    for (const PackageVolume& p : info.volumes) {
        const Volume& v = p.volume;
        volumes.push_back({{"name", v.name},
                           {"brick_cells", {v.brickCells[0], v.brickCells[1], v.brickCells[2]}},
                           {"bricks", p.brickCount},
                           {"codec", volumeCodecName(v.codec)},  // (before format 14: f32 bricks, "float")
                           {"device_bytes", p.deviceBytes()},
                           {"bounds", boundsJson(v.worldBounds)},
                           {"albedo", {v.material.albedo[0], v.material.albedo[1], v.material.albedo[2]}},
                           {"density_scale", v.material.densityScale},
                           {"anisotropy", v.material.anisotropy},
                           {"emission", p.hasEmission ? nlohmann::json{v.material.emission[0], v.material.emission[1],
                                                                        v.material.emission[2]}
                                                      : nlohmann::json()},
                           {"temperature", p.hasEmission && v.material.temperature},
                           {"data_bytes", p.size}});
    }
    nlohmann::json cameras = nlohmann::json::array();
    for (const SceneCamera& c : info.cameras)
        cameras.push_back({{"name", c.name},
                           {"eye", {c.camera.eye.x, c.camera.eye.y, c.camera.eye.z}},
                           {"target", {c.camera.target.x, c.camera.target.y, c.camera.target.z}},
                           {"up", {c.camera.up.x, c.camera.up.y, c.camera.up.z}},
                           {"fov_y_degrees", c.camera.fovYDegrees}});
    nlohmann::json lights = nlohmann::json::array();
    for (const PunctualLight& l : info.lights) {
        nlohmann::json light = {{"name", l.name},
                                {"type", lightTypeName(l.type)},
                                {"color", {l.color[0], l.color[1], l.color[2]}},
                                {"intensity", l.intensity},
                                {"range", l.range},
                                {"position", {l.position.x, l.position.y, l.position.z}},
                                {"direction", {l.direction.x, l.direction.y, l.direction.z}}};
        if (l.type == LightType::Spot)
            light["inner_cone_angle"] = l.innerConeAngle, light["outer_cone_angle"] = l.outerConeAngle;
        lights.push_back(std::move(light));
    }
    return {{"format_version", info.formatVersion},
            {"triangles", info.triangleCount},
            {"references", info.referenceCount},
            {"duplicated_references", info.duplicatedReferences()},
            {"chunks", info.chunks.size()},
            {"top_level_nodes", info.topTree.size()},
            {"chunk_size_bytes", info.chunkSizeBytes},
            {"max_chunk_resident_bytes", info.maxChunkResidentBytes},
            {"bounds", boundsJson(info.bounds)},
            {"file_bytes", info.fileBytes},
            {"quantize_bits", info.grid.bits},
            {"quantize_step", info.grid.step()},
            {"device_position_bytes", info.grid.packsPositions() ? 8 : 12},
            {"codec", geometryCodecName(info.codec)},
            {"vertex_normals", info.hasNormals},
            {"vertex_colors", info.hasColors},
            {"vertex_uvs", info.hasUvs},
            {"cameras", cameras},
            {"lights", lights},
            {"sampled_emissive_triangles", info.emitters.size()},
            {"volumes", volumes},
            {"textures", textures},
            {"degenerate_dropped", info.degenerateDropped},
            {"collapsed_dropped", info.collapsedDropped},
            {"materials", materials},
            {"chunk", chunks}};
}

void printHuman(const std::string& path, const PackageInfo& info) {
    const Aabb& b = info.bounds;
    std::printf("%s: vastray package v%u, %s\n", path.c_str(), info.formatVersion, formatBytes(info.fileBytes).c_str());
    std::printf("  triangles            %llu (+%llu duplicated references across cells)\n",
                (unsigned long long)info.triangleCount, (unsigned long long)info.duplicatedReferences());
    std::printf("  chunks               %zu (top-level tree: %zu nodes)\n", info.chunks.size(), info.topTree.size());
    std::printf("  chunk size           %s (largest chunk resident: %s)\n", formatBytes(info.chunkSizeBytes).c_str(),
                formatBytes(info.maxChunkResidentBytes).c_str());
    std::printf("  bounds               (%g, %g, %g) .. (%g, %g, %g)\n", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z);
    if (info.grid.bits)
        std::printf("  quantization         %u bits, step %.3g (device positions: %s)\n", info.grid.bits,
                    info.grid.step(), info.grid.packsPositions() ? "8 bytes a vertex" : "12 bytes a vertex");
    else
        std::printf("  quantization         lossless (device positions: 12 bytes a vertex)\n");
    std::printf("  chunk codec          %s\n", geometryCodecName(info.codec));
    std::string attributes;
    for (auto [present, name] : {std::pair{info.hasNormals, "shading normals"}, {info.hasColors, "colours"},
                                 {info.hasUvs, "texture coordinates"}})
        if (present) attributes += (attributes.empty() ? "" : ", ") + std::string(name);
    std::printf("  vertex attributes    %s\n", attributes.empty() ? "none" : attributes.c_str());
    const auto cutouts = std::count_if(info.materials.begin(), info.materials.end(),
                                       [&](const Material& m) { return isCutout(m, info.textures.size()); });
    const auto blends = std::count_if(info.materials.begin(), info.materials.end(),
                                      [&](const Material& m) { return isBlended(m, info.textures.size()); });
    std::string alpha;
    if (cutouts > 0) alpha = std::to_string(cutouts) + " alpha cut-outs";
    if (blends > 0) alpha += (alpha.empty() ? "" : ", ") + std::to_string(blends) + " blended";
    if (!alpha.empty())
        std::printf("  materials            %zu (%s)\n", info.materials.size(), alpha.c_str());
    else
        std::printf("  materials            %zu\n", info.materials.size());
    if (!info.emitters.empty())
        std::printf("  emissive triangles   %zu (sampled as lights)\n", info.emitters.size());
    for (uint32_t t = 0; t < info.textures.size(); ++t) {
        const PackageTexture& x = info.textures[t];
        std::printf("  texture %-12u '%s': %u x %u texels, %u levels, %u pages (%s stored), %s, wrap %s/%s\n", t,
                    x.name.c_str(), x.layout.width, x.layout.height, x.layout.levelCount, x.layout.pageCount,
                    formatBytes(textureStoredBytes(info, t)).c_str(),
                    x.encoding == TextureEncoding::Srgb ? "sRGB" : "linear", textureWrapName(x.wrapS),
                    textureWrapName(x.wrapT));
    }
    for (size_t i = 0; i < info.cameras.size(); ++i) {
        const Camera& c = info.cameras[i].camera;
        std::printf("  camera %-13zu '%s': eye (%g, %g, %g), looking at (%g, %g, %g), fov %g degrees\n", i,
                    info.cameras[i].name.c_str(), c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z,
                    c.fovYDegrees);
    }
    for (size_t i = 0; i < info.lights.size(); ++i) {
        const PunctualLight& l = info.lights[i];
        std::printf("  light %-14zu '%s': %s, colour (%g, %g, %g), intensity %g %s", i, l.name.c_str(),
                    lightTypeName(l.type), l.color[0], l.color[1], l.color[2], l.intensity,
                    l.type == LightType::Directional ? "lux" : "cd");
        if (l.type != LightType::Directional) std::printf(", at (%g, %g, %g)", l.position.x, l.position.y, l.position.z);
        if (l.type != LightType::Point)
            std::printf(", shining along (%g, %g, %g)", l.direction.x, l.direction.y, l.direction.z);
        if (l.type == LightType::Spot) std::printf(", cone %g..%g rad", l.innerConeAngle, l.outerConeAngle);
        if (l.range > 0) std::printf(", range %g (not rendered)", l.range);
        std::printf("\n");
    }
    for (size_t i = 0; i < info.volumes.size(); ++i) {
        const PackageVolume& p = info.volumes[i];
        const Volume& v = p.volume;
        std::printf("  volume %-13zu '%s': %u x %u x %u brick cells, %u bricks (%s, %s), albedo (%g, %g, "
                    "%g), density x%g, anisotropy %g",
                    i, v.name.c_str(), v.brickCells[0], v.brickCells[1], v.brickCells[2], p.brickCount,
                    formatBytes(p.size).c_str(),
                    info.formatVersion >= 14 ? (std::string("NanoVDB ") + volumeCodecName(v.codec) + " leaves").c_str()
                                             : "f32 bricks",
                    v.material.albedo[0], v.material.albedo[1], v.material.albedo[2],
                    v.material.densityScale, v.material.anisotropy);
        if (p.hasEmission)
            std::printf(", %s x(%g, %g, %g)", v.material.temperature ? "blackbody of a temperature grid" : "emission",
                        v.material.emission[0], v.material.emission[1], v.material.emission[2]);
        std::printf("\n");
    }
    std::printf("  dropped              %llu degenerate at import, %llu collapsed by quantization\n",
                (unsigned long long)info.degenerateDropped, (unsigned long long)info.collapsedDropped);
}

}  // namespace

CommandRun addInfoCommand(CLI::App& app) {
    struct Args {
        std::string path, exportCells;
        bool verify = false, json = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("info", "Describe a scene package; optionally verify it or export its cells.");
    cmd->add_option("scene", args->path, "scene package (.vast)")->required()->check(CLI::ExistingFile);
    cmd->add_flag("--verify", args->verify,
                  "read and decode every chunk, check checksums and structure; exit 1 naming each damaged chunk");
    cmd->add_flag("--json", args->json, "print machine-readable JSON (with a per-chunk array)");
    cmd->add_option("--export-cells", args->exportCells,
                    "write every cell's box tagged with its chunk id (.obj or .ply) for Blender/Houdini");
    return [args]() {
        auto reader = PackageReader::open(args->path);
        if (!reader) {
            std::fprintf(stderr, "vastray info: %s\n", reader.message().c_str());
            return 1;
        }
        const PackageInfo& info = (*reader)->info();
        if (!args->exportCells.empty()) {
            if (Status s = exportCells(info, args->exportCells); !s) {
                std::fprintf(stderr, "vastray info: %s\n", s.message().c_str());
                return 1;
            }
        }
        std::vector<std::string> problems;
        if (args->verify) problems = (*reader)->verify();
        if (args->json) {
            nlohmann::json j = infoJson(info);
            if (args->verify) j["verify"] = {{"ok", problems.empty()}, {"problems", problems}};
            std::printf("%s\n", j.dump(2).c_str());
        } else {
            printHuman(args->path, info);
            if (!args->exportCells.empty()) std::printf("  cells written to     %s\n", args->exportCells.c_str());
            if (args->verify && problems.empty())
                std::printf("  verify               all %zu chunks%s intact\n", info.chunks.size(),
                            info.volumes.empty() ? "" : (" and " + std::to_string(info.volumes.size()) + " volumes").c_str());
        }
        for (const std::string& p : problems) std::fprintf(stderr, "%s\n", p.c_str());
        if (!problems.empty())
            std::fprintf(stderr, "vastray info: %zu of %zu chunks damaged\n", problems.size(), info.chunks.size());
        return problems.empty() ? 0 : 1;
    };
}

}  // namespace vastray::cli

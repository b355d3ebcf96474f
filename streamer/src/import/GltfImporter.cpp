// glTF 2.0 (.gltf/.glb): flattens the default scene's node hierarchy into world-space
// triangles. Each node that references a mesh produces its own copy (instancing).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "import/GltfAccessor.h"
#include "import/GltfLoader.h"
#include "import/GltfTextures.h"
#include "import/ImportCommon.h"
#include "vastray/core/Utf8.h"
#include "vastray/core/VecMath.h"
#include "vastray/core/VertexAttributes.h"
#include "vastray/streamer/Import.h"

namespace vastray {
namespace {

using Mat4 = std::array<double, 16>;  // column-major, as glTF stores it

constexpr Mat4 kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Mat4 multiply(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row)
            for (int k = 0; k < 4; ++k) r[c * 4 + row] += a[k * 4 + row] * b[c * 4 + k];
    return r;
}

// T * R * S (glTF 2.0 spec 3.5.3); rotation is a unit quaternion (x, y, z, w).
Mat4 localTransform(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
        Mat4 m;
        std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
        return m;
    }
    const std::vector<double> t = n.translation.size() == 3 ? n.translation : std::vector<double>{0, 0, 0};
    const std::vector<double> q = n.rotation.size() == 4 ? n.rotation : std::vector<double>{0, 0, 0, 1};
    const std::vector<double> s = n.scale.size() == 3 ? n.scale : std::vector<double>{1, 1, 1};
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const Mat4 r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
                    2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
                    2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
                    0,                       0,                       0,                       1};
    Mat4 m = r;
    for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row) m[c * 4 + row] *= s[c];
    m[12] = t[0], m[13] = t[1], m[14] = t[2];
    return m;
}

double determinant3(const Mat4& m) {
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}

// Normals transform with the inverse transpose of the upper 3x3: the cofactor matrix divided by
// the determinant; only its sign matters before normalizing. Column-major, as Mat4.
std::array<double, 9> normalMatrix(const Mat4& m) {
    auto at = [&](int row, int column) { return m[column * 4 + row]; };
    std::array<double, 9> c{};
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) {
            const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
            c[k * 3 + r] = at(r1, k1) * at(r2, k2) - at(r1, k2) * at(r2, k1);
        }
    if (determinant3(m) < 0)
        for (double& v : c) v = -v;
    return c;
}

Material convertMaterial(const tinygltf::Material& g, size_t index) {
    Material m;
    m.name = g.name.empty() ? "material " + std::to_string(index) : g.name;
    const auto& base = g.pbrMetallicRoughness.baseColorFactor;
    for (size_t i = 0; i < 4 && i < base.size(); ++i) m.baseColor[i] = float(base[i]);
    double strength = 1.0;
    const auto ext = g.extensions.find("KHR_materials_emissive_strength");
    if (ext != g.extensions.end() && ext->second.Has("emissiveStrength"))
        strength = ext->second.Get("emissiveStrength").GetNumberAsDouble();
    for (size_t i = 0; i < 3 && i < g.emissiveFactor.size(); ++i) m.emissive[i] = float(g.emissiveFactor[i] * strength);
    m.doubleSided = g.doubleSided;
    // Metallic-roughness (tinygltf fills the spec's defaults, 1 and 1); KHR_materials_specular's
    // factor weights the dielectric layer (1 without it) and its colour factor scales the layer's
    // F0 (white without it). The types were checked (GltfSchema); out-of-range factors are refused
    // by finalizeMesh; the maps are read by GltfTextures.
    m.metallic = float(g.pbrMetallicRoughness.metallicFactor);
    m.roughness = float(g.pbrMetallicRoughness.roughnessFactor);
    m.specular = 1.0f;
    const auto specular = g.extensions.find("KHR_materials_specular");
    if (specular != g.extensions.end() && specular->second.Has("specularFactor")) {
        const tinygltf::Value& factor = specular->second.Get("specularFactor");
        m.specular = factor.IsNumber() ? float(factor.GetNumberAsDouble()) : std::numeric_limits<float>::quiet_NaN();
    }
    if (specular != g.extensions.end() && specular->second.Has("specularColorFactor")) {
        const tinygltf::Value& colour = specular->second.Get("specularColorFactor");
        for (int c = 0; c < 3; ++c)
            m.specularColor[c] = colour.IsArray() && colour.ArrayLen() == 3 && colour.Get(c).IsNumber()
                                     ? float(colour.Get(c).GetNumberAsDouble())
                                     : std::numeric_limits<float>::quiet_NaN();
    }
    // KHR_materials_ior's index of refraction (1.5 without it; its range: finalizeMesh).
    if (const auto ior = g.extensions.find("KHR_materials_ior"); ior != g.extensions.end() && ior->second.Has("ior")) {
        const tinygltf::Value& v = ior->second.Get("ior");
        m.ior = v.IsNumber() ? float(v.GetNumberAsDouble()) : std::numeric_limits<float>::quiet_NaN();
    }
    // KHR_materials_clearcoat's factors (0 and 0 without it: no coat).
    if (const auto coat = g.extensions.find("KHR_materials_clearcoat"); coat != g.extensions.end()) {
        const auto factor = [&](const char* name) {
            if (!coat->second.Has(name)) return 0.0f;
            const tinygltf::Value& v = coat->second.Get(name);
            return v.IsNumber() ? float(v.GetNumberAsDouble()) : std::numeric_limits<float>::quiet_NaN();
        };
        m.clearcoat = factor("clearcoatFactor");
        m.clearcoatRoughness = factor("clearcoatRoughnessFactor");
    }
    // alphaMode MASK with a base colour map: the map's alpha cuts the surface out where the
    // product falls below alphaCutoff (docs/RENDERING.md, "Cut-outs"); a factor alone below it
    // hides the triangles (hiddenByAlpha, left out at import).
    if (g.alphaMode == "MASK" && g.pbrMetallicRoughness.baseColorTexture.index >= 0)
        m.alphaCutoff = float(std::clamp(g.alphaCutoff, 0.0, 1.0));
    // alphaMode BLEND: the surface is there with the probability of its alpha ("Cut-outs and
    // blending"); at alpha 0 it is left out (hiddenByAlpha).
    m.alphaBlend = g.alphaMode == "BLEND";
    return m;
}

// A material its alpha hides whatever its texture and vertex colours say (they only multiply
// baseColorFactor's alpha): alphaMode MASK with the factor below alphaCutoff, or BLEND at alpha
// 0. Its triangles are left out at import (counted; nothing else could show them).
double factorAlpha(const tinygltf::Material& g) {
    const auto& base = g.pbrMetallicRoughness.baseColorFactor;
    return base.size() == 4 ? base[3] : 1.0;
}
bool hiddenByAlpha(const tinygltf::Material& g) {
    const double alpha = factorAlpha(g);
    return (g.alphaMode == "MASK" && alpha < g.alphaCutoff) || (g.alphaMode == "BLEND" && alpha <= 0.0);
}

class GltfFlattener {
public:
    GltfFlattener(const tinygltf::Model& model, std::vector<PunctualLight> lights, ImportedMesh& out)
        : model_(model), out_(out), templates_(std::move(lights)) {
        for (size_t i = 0; i < model.materials.size(); ++i) out_.mesh.materials.push_back(convertMaterial(model.materials[i], i));
    }

    void keepUvSet(int set) { uvSet_ = set; }

    Status run() {
        std::vector<int> roots = rootNodes();
        std::vector<uint8_t> visited(model_.nodes.size(), 0);
        std::vector<std::pair<int, Mat4>> stack;
        for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, kIdentity);
        while (!stack.empty()) {
            const auto [index, parent] = stack.back();
            stack.pop_back();
            if (index < 0 || size_t(index) >= model_.nodes.size())
                return Status::error("node " + std::to_string(index) + " does not exist");
            // glTF node graphs are strict trees; a second visit means a cycle or a shared child.
            if (visited[index]++) return Status::error("node " + std::to_string(index) + " is reached twice (cycle or shared child)");
            const tinygltf::Node& node = model_.nodes[index];
            const Mat4 world = multiply(parent, localTransform(node));
            if (node.mesh >= 0) {
                if (Status s = addMesh(node.mesh, world); !s.isOk()) return s;
            }
            if (node.camera >= 0) addCamera(node, world);
            if (Status s = addLight(index, node, world); !s.isOk()) return s;
            for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.emplace_back(*c, world);
        }
        // In the order of the file's cameras (a camera placed by two nodes twice, in visiting order).
        std::stable_sort(cameras_.begin(), cameras_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (auto& [index, camera] : cameras_) out_.mesh.cameras.push_back(std::move(camera));
        std::stable_sort(lights_.begin(), lights_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        std::vector<uint8_t> placed(templates_.size(), 0);
        for (auto& [index, light] : lights_) {
            placed[index] = 1;
            out_.mesh.lights.push_back(std::move(light));
        }
        lightsNotUsed_ += uint64_t(std::count(placed.begin(), placed.end(), 0));
        return Status::ok();
    }

    uint64_t camerasNotUsed() const { return camerasNotUsed_; }
    uint64_t lightsNotUsed() const { return lightsNotUsed_; }
    uint64_t hiddenTriangles() const { return hiddenTriangles_; }

private:
    // The default scene, else scene 0, else every node that is nobody's child.
    std::vector<int> rootNodes() const {
        if (!model_.scenes.empty()) {
            const int s = model_.defaultScene >= 0 && size_t(model_.defaultScene) < model_.scenes.size() ? model_.defaultScene : 0;
            return model_.scenes[s].nodes;
        }
        std::vector<uint8_t> isChild(model_.nodes.size(), 0);
        for (const tinygltf::Node& n : model_.nodes)
            for (int c : n.children)
                if (c >= 0 && size_t(c) < isChild.size()) isChild[c] = 1;
        std::vector<int> roots;
        for (size_t i = 0; i < isChild.size(); ++i)
            if (!isChild[i]) roots.push_back(int(i));
        return roots;
    }

    Status addMesh(int meshIndex, const Mat4& world) {
        if (size_t(meshIndex) >= model_.meshes.size()) return Status::error("mesh " + std::to_string(meshIndex) + " does not exist");
        const auto& prims = model_.meshes[meshIndex].primitives;
        for (size_t p = 0; p < prims.size(); ++p) {
            const std::string where = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p) + ": ";
            if (Status s = addPrimitive(prims[p], world); !s.isOk()) return s.withContext(where);
        }
        return Status::ok();
    }

    // A perspective camera node: it looks down its local -Z with +Y up (spec 3.10); the image's
    // aspect ratio is the render's --resolution, not the camera's aspectRatio. Orthographic
    // cameras and ones whose placement is degenerate are counted as not used.
    void addCamera(const tinygltf::Node& node, const Mat4& m) {
        if (size_t(node.camera) >= model_.cameras.size() || model_.cameras[node.camera].type != "perspective") {
            ++camerasNotUsed_;
            return;
        }
        const tinygltf::Camera& c = model_.cameras[node.camera];
        SceneCamera scene;
        scene.name = !c.name.empty() ? c.name : !node.name.empty() ? node.name : "camera " + std::to_string(node.camera);
        const Vec3f eye{float(m[12]), float(m[13]), float(m[14])};
        const Vec3f forward = normalize(Vec3f{float(-m[8]), float(-m[9]), float(-m[10])});
        scene.camera.eye = eye;
        scene.camera.target = eye + forward * std::max(1.0f, length(eye));
        scene.camera.up = normalize(Vec3f{float(m[4]), float(m[5]), float(m[6])});
        scene.camera.fovYDegrees = float(c.perspective.yfov * 180.0 / 3.14159265358979323846);
        if (!validateCamera(scene.camera).isOk()) {
            ++camerasNotUsed_;
            return;
        }
        cameras_.emplace_back(node.camera, std::move(scene));
    }

    // A node's KHR_lights_punctual light, placed at the node's origin and shining down its local
    // -Z (the extension's spec); the lights in the file's order (a light placed by two nodes twice,
    // in visiting order). A light whose placement is degenerate (a zero scale) is counted as not used.
    Status addLight(int nodeIndex, const tinygltf::Node& node, const Mat4& m) {
        const auto ext = node.extensions.find("KHR_lights_punctual");
        if (ext == node.extensions.end()) return Status::ok();
        const std::string where = "JSON /nodes/" + std::to_string(nodeIndex) + "/extensions/KHR_lights_punctual/light";
        const tinygltf::Value& index = ext->second.Get("light");
        const int light = index.IsInt() ? index.GetNumberAsInt() : -1;
        if (light < 0 || size_t(light) >= templates_.size())
            return Status::error(where + ": light " + std::to_string(light) + " does not exist (" +
                                 std::to_string(templates_.size()) + " lights)");
        if (lights_.size() >= kMaxLights)
            return Status::error(where + ": more than " + std::to_string(kMaxLights) + " lights are placed (the limit)");
        PunctualLight placed = templates_[light];
        if (placed.name.empty()) placed.name = storedCameraName(!node.name.empty() ? node.name : "light " + std::to_string(light));
        placed.position = {float(m[12]), float(m[13]), float(m[14])};
        const Vec3f down{float(-m[8]), float(-m[9]), float(-m[10])};
        if (!(length(down) > 0.0f)) return Status::ok();  // counted as not used unless another node places it
        placed.direction = normalize(down);
        if (Status s = validateLight(placed); !s.isOk()) return s.withContext("JSON /nodes/" + std::to_string(nodeIndex) + ": ");
        lights_.emplace_back(light, std::move(placed));
        return Status::ok();
    }

    Status addPrimitive(const tinygltf::Primitive& prim, const Mat4& world) {
        if (prim.mode >= TINYGLTF_MODE_POINTS && prim.mode <= TINYGLTF_MODE_LINE_STRIP) {
            ++out_.report.primitivesSkipped;
            return Status::ok();
        }
        if (prim.mode < TINYGLTF_MODE_TRIANGLES || prim.mode > TINYGLTF_MODE_TRIANGLE_FAN)
            return Status::error("unknown primitive mode " + std::to_string(prim.mode));
        const auto position = prim.attributes.find("POSITION");
        if (position == prim.attributes.end()) return Status::error("no POSITION attribute");
        if (Status s = import::readVec3Accessor(model_, position->second, xyz_); !s.isOk()) return s;
        const uint64_t vertexCount = xyz_.size() / 3;
        if (Status s = readCorners(prim, vertexCount); !s.isOk()) return s;
        const uint64_t base = out_.mesh.positions.size();
        if (base + vertexCount > std::numeric_limits<uint32_t>::max())
            return Status::error("total vertex count " + std::to_string(base + vertexCount) + " exceeds the uint32 index range");
        countAttributes(prim);
        appendPositions(world);
        if (Status s = appendNormals(prim, world, vertexCount); !s.isOk()) return s;
        if (Status s = appendColours(prim, vertexCount); !s.isOk()) return s;
        if (Status s = appendUvs(prim, vertexCount); !s.isOk()) return s;
        return appendTriangles(prim, uint32_t(base), determinant3(world) < 0);
    }

    // The accessor of `attribute` on `prim`, the primitive whose positions were appended last.
    // Without it: none, and once earlier primitives gave the mesh that attribute (`values` not
    // empty), this primitive's vertices get `fill`: a mesh has it on every vertex or on none.
    // With it, the caller reads it and pads the vertices before this primitive with `fill`.
    template <typename T>
    std::optional<int> attributeOrFill(const tinygltf::Primitive& prim, const char* attribute, std::vector<T>& values,
                                       T fill) {
        const auto found = prim.attributes.find(attribute);
        if (found != prim.attributes.end()) return found->second;
        if (!values.empty()) values.resize(out_.mesh.positions.size(), fill);
        return std::nullopt;
    }

    // NORMAL in world space. The mesh has normals on every vertex or none: once a primitive has
    // them, the vertices of those without get kNoNormal (the geometric normal is used there).
    Status appendNormals(const tinygltf::Primitive& prim, const Mat4& world, uint64_t vertexCount) {
        std::vector<uint32_t>& normals = out_.mesh.normals;
        const std::optional<int> normal = attributeOrFill(prim, "NORMAL", normals, kNoNormal);
        if (!normal) return Status::ok();
        if (Status s = import::readVec3Accessor(model_, *normal, xyz_, "NORMAL"); !s.isOk()) return s;
        if (xyz_.size() / 3 != vertexCount)
            return Status::error("NORMAL has " + std::to_string(xyz_.size() / 3) + " elements for " +
                                 std::to_string(vertexCount) + " positions");
        normals.resize(out_.mesh.positions.size() - vertexCount, kNoNormal);
        const std::array<double, 9> n = normalMatrix(world);
        for (size_t i = 0; i < xyz_.size(); i += 3) {
            const double x = xyz_[i], y = xyz_[i + 1], z = xyz_[i + 2];
            normals.push_back(encodeOctahedral({float(n[0] * x + n[3] * y + n[6] * z),
                                                float(n[1] * x + n[4] * y + n[7] * z),
                                                float(n[2] * x + n[5] * y + n[8] * z)}));
        }
        return Status::ok();
    }

    // COLOR_0 (linear, spec 3.7.2.1), white on the vertices of primitives without once any has it.
    Status appendColours(const tinygltf::Primitive& prim, uint64_t vertexCount) {
        std::vector<uint32_t>& colours = out_.mesh.colors;
        const std::optional<int> colour = attributeOrFill(prim, "COLOR_0", colours, kWhiteColor);
        if (!colour) return Status::ok();
        if (Status s = import::readColorAccessor(model_, *colour, rgb_); !s.isOk()) return s;
        if (rgb_.size() / 3 != vertexCount)
            return Status::error("COLOR_0 has " + std::to_string(rgb_.size() / 3) + " elements for " +
                                 std::to_string(vertexCount) + " positions");
        colours.resize(out_.mesh.positions.size() - vertexCount, kWhiteColor);
        for (size_t i = 0; i < rgb_.size(); i += 3)
            colours.push_back(packLinearColor(float(rgb_[i]), float(rgb_[i + 1]), float(rgb_[i + 2])));
        out_.report.coloursRead += vertexCount;
        return Status::ok();
    }

    // TEXCOORD_<uvSet_> (uvSet_ < 0: no material has a texture, nothing is read), (0, 0) on the
    // vertices of primitives without once any has it. glTF's texture space is the package's.
    Status appendUvs(const tinygltf::Primitive& prim, uint64_t vertexCount) {
        if (uvSet_ < 0) return Status::ok();
        const std::string attribute = "TEXCOORD_" + std::to_string(uvSet_);
        std::vector<std::array<float, 2>>& uvs = out_.mesh.uvs;
        const std::optional<int> uv = attributeOrFill(prim, attribute.c_str(), uvs, std::array<float, 2>{0.0f, 0.0f});
        if (!uv) return Status::ok();
        if (Status s = import::readUvAccessor(model_, *uv, attribute, rgb_); !s.isOk()) return s;
        if (rgb_.size() / 2 != vertexCount)
            return Status::error(attribute + " has " + std::to_string(rgb_.size() / 2) + " elements for " +
                                 std::to_string(vertexCount) + " positions");
        uvs.resize(out_.mesh.positions.size() - vertexCount, {0.0f, 0.0f});
        for (size_t i = 0; i < rgb_.size(); i += 2) uvs.push_back({float(rgb_[i]), float(rgb_[i + 1])});
        return Status::ok();
    }

    Status readCorners(const tinygltf::Primitive& prim, uint64_t vertexCount) {
        if (prim.indices >= 0) {
            if (Status s = import::readIndexAccessor(model_, prim.indices, corners_); !s.isOk()) return s;
        } else {
            corners_.resize(vertexCount);
            for (uint64_t i = 0; i < vertexCount; ++i) corners_[i] = uint32_t(i);
        }
        for (size_t i = 0; i < corners_.size(); ++i)
            if (corners_[i] >= vertexCount)
                return Status::error("index " + std::to_string(i) + " value " + std::to_string(corners_[i]) +
                                     " >= vertex count " + std::to_string(vertexCount));
        if (prim.mode == TINYGLTF_MODE_TRIANGLE_FAN && corners_.size() > import::kMaxFanCorners)
            return Status::error("triangle fan of " + std::to_string(corners_.size()) +
                                 " corners exceeds the fan limit of " + std::to_string(import::kMaxFanCorners));
        if (prim.mode == TINYGLTF_MODE_TRIANGLES && corners_.size() % 3 != 0)
            return Status::error((prim.indices >= 0 ? "index count " : "vertex count ") + std::to_string(corners_.size()) +
                                 " is not a multiple of 3");
        return Status::ok();
    }

    void countAttributes(const tinygltf::Primitive& prim) {
        const uint64_t count = xyz_.size() / 3;
        out_.report.verticesRead += count;
        if (prim.attributes.count("NORMAL")) out_.report.normalsRead += count;
        if (prim.attributes.count("TEXCOORD_" + std::to_string(std::max(uvSet_, 0)))) out_.report.texcoordsRead += count;
    }

    void appendPositions(const Mat4& m) {
        for (size_t i = 0; i < xyz_.size(); i += 3) {
            const double x = xyz_[i], y = xyz_[i + 1], z = xyz_[i + 2];
            out_.mesh.positions.push_back({float(m[0] * x + m[4] * y + m[8] * z + m[12]),
                                           float(m[1] * x + m[5] * y + m[9] * z + m[13]),
                                           float(m[2] * x + m[6] * y + m[10] * z + m[14])});
        }
    }

    uint32_t materialId(int material) {
        if (material >= 0 && size_t(material) < model_.materials.size()) return uint32_t(material);
        if (defaultMaterial_ < 0) {
            Material m{"default"};
            m.baseColor = {1, 1, 1, 1};  // glTF default material (spec 3.9.6): metallic and rough
            m.metallic = m.roughness = m.specular = 1.0f;
            m.doubleSided = false;
            defaultMaterial_ = int64_t(out_.mesh.materials.size());
            out_.mesh.materials.push_back(m);
        }
        return uint32_t(defaultMaterial_);
    }

    // A mirroring transform (negative determinant) flips winding; swapping two corners
    // restores it so that front faces stay front (glTF 2.0 spec 3.7.4).
    Status appendTriangles(const tinygltf::Primitive& prim, uint32_t base, bool mirrored) {
        if (prim.material >= 0 && size_t(prim.material) >= model_.materials.size())
            return Status::error("material " + std::to_string(prim.material) + " does not exist");
        const uint32_t material = materialId(prim.material);
        const bool hidden = prim.material >= 0 && hiddenByAlpha(model_.materials[size_t(prim.material)]);
        auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
            if (hidden) {
                ++hiddenTriangles_;
                return;
            }
            if (mirrored) std::swap(b, c);
            out_.mesh.indices.insert(out_.mesh.indices.end(), {base + a, base + b, base + c});
            out_.mesh.materialIds.push_back(material);
        };
        const std::vector<uint32_t>& v = corners_;
        if (prim.mode == TINYGLTF_MODE_TRIANGLES)
            for (size_t i = 0; i + 2 < v.size(); i += 3) emit(v[i], v[i + 1], v[i + 2]);
        else if (prim.mode == TINYGLTF_MODE_TRIANGLE_STRIP)
            for (size_t i = 0; i + 2 < v.size(); ++i) i % 2 == 0 ? emit(v[i], v[i + 1], v[i + 2]) : emit(v[i + 1], v[i], v[i + 2]);
        else
            for (size_t i = 1; i + 1 < v.size(); ++i) emit(v[0], v[i], v[i + 1]);
        return Status::ok();
    }

    const tinygltf::Model& model_;
    ImportedMesh& out_;
    std::vector<double> xyz_;        // reused per primitive
    std::vector<double> rgb_;        // reused per primitive (colours, UVs)
    int uvSet_ = -1;                 // the TEXCOORD_n kept (chooseUvSet), -1: none
    std::vector<uint32_t> corners_;  // reused per primitive
    int64_t defaultMaterial_ = -1;
    std::vector<std::pair<int, SceneCamera>> cameras_;  // glTF camera index, camera
    uint64_t camerasNotUsed_ = 0;
    const std::vector<PunctualLight> templates_;  // the file's lights, checked, not placed (readLights)
    std::vector<std::pair<int, PunctualLight>> lights_;  // glTF light index, placed light
    uint64_t lightsNotUsed_ = 0;
    uint64_t hiddenTriangles_ = 0;  // of materials their alpha hides (hiddenByAlpha), left out
};

// The document's KHR_lights_punctual lights, each checked against the extension's rules and
// vastray's limits (core/Light.h): "JSON /extensions/KHR_lights_punctual/lights/3: intensity ...".
Result<std::vector<PunctualLight>> readLights(const tinygltf::Model& model) {
    const std::string root = "JSON /extensions/KHR_lights_punctual/lights";
    if (model.lights.size() > kMaxLights)
        return Status::error(root + ": " + std::to_string(model.lights.size()) + " lights exceed the limit of " +
                             std::to_string(kMaxLights));
    std::vector<PunctualLight> lights;
    for (size_t i = 0; i < model.lights.size(); ++i) {
        const tinygltf::Light& g = model.lights[i];
        const std::string where = root + "/" + std::to_string(i) + ": ";
        PunctualLight l;
        if (g.type == "directional") l.type = LightType::Directional;
        else if (g.type == "point") l.type = LightType::Point;
        else if (g.type == "spot") l.type = LightType::Spot;
        else return Status::error(where + "type '" + g.type + "' is not directional, point or spot");
        l.name = storedCameraName(g.name);  // cut as a package keeps it (kMaxLightNameBytes)
        for (size_t c = 0; c < 3 && c < g.color.size(); ++c) l.color[c] = float(g.color[c]);
        l.intensity = float(g.intensity);
        l.range = float(g.range);
        if (g.range < 0.0 || (g.range == 0.0 && std::signbit(g.range)))
            return Status::error(where + "range " + std::to_string(g.range) + " is not above 0");
        l.innerConeAngle = float(g.spot.innerConeAngle), l.outerConeAngle = float(g.spot.outerConeAngle);
        if (Status s = validateLight(l); !s.isOk()) return s.withContext(where);
        lights.push_back(std::move(l));
    }
    return lights;
}

// The UV set the materials' textures use (textureInfo.texCoord of the maps read: gltfMaterialMaps), the
// most used when they differ (warned, naming the file), -1 when no material has a texture:
// then no UVs are kept. Counts the maps into report.textureMaps.
int chooseUvSet(const tinygltf::Model& model, const std::string& name, ImportReport& report) {
    std::map<int, uint64_t> uses;
    for (const tinygltf::Material& m : model.materials)
        for (const import::GltfMapInfo& map : import::gltfMaterialMaps(m))
            if (map.index >= 0) ++uses[std::max(map.texCoord, 0)], ++report.textureMaps;
    if (uses.empty()) return -1;
    const auto most = std::max_element(uses.begin(), uses.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    if (uses.size() > 1)
        report.warnings.push_back(name + ": materials' textures use " + std::to_string(uses.size()) +
                                  " UV sets; TEXCOORD_" + std::to_string(most->first) +
                                  " (the most used) is kept, textures on the others will be placed by it");
    return most->first;
}

// Warns once per name (what(name) read but not used, with `consequence`), the most used first
// (then by name); a hostile file may name thousands: past eight, one line for the others.
void warnByName(const std::map<std::string, uint64_t>& counts, const std::function<std::string(const std::string&)>& what,
                const std::string& consequence, const std::string& others, const std::string& othersConsequence,
                ImportReport& report) {
    constexpr size_t kNamed = 8;
    std::vector<std::pair<std::string, uint64_t>> byUse(counts.begin(), counts.end());
    std::stable_sort(byUse.begin(), byUse.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    uint64_t rest = 0;
    size_t named = 0;
    for (const auto& [name, count] : byUse) {
        if (named++ < kNamed)
            report.warnUnused(what(cutUtf8(validUtf8(name), 64)), count, consequence);
        else
            rest += count;
    }
    report.warnUnused(others, rest, othersConsequence);
}

// What the file holds that the package does not carry, once per kind. `uvSet`: the TEXCOORD set
// kept (chooseUvSet; -1: none).
void warnAboutUnused(const tinygltf::Model& model, int uvSet, ImportReport& report) {
    uint64_t morphs = 0;
    // Vertex attributes the package does not carry, per primitive (skins' JOINTS_n and WEIGHTS_n
    // are the skins' warning; UVs without a texture map, Import.cpp's).
    std::map<std::string, uint64_t> attributes;
    const std::string keptUvs = "TEXCOORD_" + std::to_string(uvSet);
    for (const tinygltf::Mesh& mesh : model.meshes)
        for (const tinygltf::Primitive& prim : mesh.primitives) {
            morphs += prim.targets.size();
            for (const auto& [name, accessor] : prim.attributes)
                if (name != "POSITION" && name != "NORMAL" && name != "COLOR_0" && name != keptUvs &&
                    !(uvSet < 0 && name.starts_with("TEXCOORD_")) &&  // "no material has a texture map"
                    !name.starts_with("JOINTS_") && !name.starts_with("WEIGHTS_"))
                    ++attributes[name];
        }
    if (const auto tangents = attributes.find("TANGENT"); tangents != attributes.end()) {
        report.warnUnused("primitives' TANGENT attributes", tangents->second,
                          "normal maps take their frames from the UVs: docs/RENDERING.md, \"Normal maps\"");
        attributes.erase(tangents);
    }
    warnByName(
        attributes, [](const std::string& name) { return "primitives' " + name + " attributes"; },
        "not stored in the package", "primitives' other vertex attributes", "not stored in the package", report);
    report.warnUnused("morph targets", morphs);
    report.warnUnused("skins", model.skins.size());
    report.warnUnused("animations", model.animations.size());
    uint64_t coatTextures = 0;
    for (const tinygltf::Material& m : model.materials)
        if (const auto coat = m.extensions.find("KHR_materials_clearcoat"); coat != m.extensions.end())
            coatTextures += coat->second.Has("clearcoatNormalTexture") ? 1 : 0;
    report.warnUnused("KHR_materials_clearcoat normal textures", coatTextures,
                      "the coat takes the surface's shading normal");
    // Material extensions the renderer has no model for (transmission, sheen, volume, ...),
    // each counted by name, so that glass rendered opaque is not a surprise.
    std::map<std::string, uint64_t> extensions;
    for (const tinygltf::Material& m : model.materials)
        for (const auto& [name, value] : m.extensions)
            if (name != "KHR_materials_emissive_strength" && name != "KHR_materials_specular" &&
                name != "KHR_materials_clearcoat" && name != "KHR_materials_ior")
                ++extensions[name];
    warnByName(
        extensions, [](const std::string& name) { return "materials' " + name + " extensions"; },
        "the material is rendered without it", "other material extensions", "rendered without them", report);
}

Result<ImportedMesh> importGltfUnguarded(const std::string& path, const ImportOptions& options) {
    const std::string name = import::fileNameOf(path);
    const bool binary = import::lowerExtension(path) == "glb";
    bool version1 = false;
    auto model = import::loadGltfModel(path, binary, &version1);
    if (version1 && binary)  // assimp 5.2 reads text glTF 1.0 only
        return import::errorIn(name, "GLB header: version 1 (binary glTF 1.0) is not supported; convert the file "
                                     "to glTF 2.0 (e.g. gltf-pipeline) or to text glTF 1.0");
    if (version1) return importWithAssimp(path, options);  // assimp reads glTF 1.0
    if (!model) return model.status();
    ImportedMesh imported;
    imported.report.format = binary ? "glb" : "gltf";
    auto lights = readLights(*model);
    if (!lights) return lights.status().withContext(name + ": ");
    GltfFlattener flattener(*model, std::move(lights).value(), imported);
    const int uvSet = chooseUvSet(*model, name, imported.report);
    flattener.keepUvSet(uvSet);
    if (Status s = flattener.run(); !s.isOk()) return s.withContext(name + ": ");
    auto textures = import::readGltfTextures(*model, name, import::directoryOf(path), imported.report);
    if (!textures) return textures.status();
    for (size_t i = 0; i < textures->materials.size(); ++i) imported.mesh.materials[i].textures = textures->materials[i];
    imported.mesh.textures = std::move(textures->textures);
    warnAboutUnused(*model, uvSet, imported.report);
    imported.report.warnUnused("cameras", flattener.camerasNotUsed(), "orthographic, or placed degenerately");
    imported.report.warnUnused("KHR_lights_punctual lights", flattener.lightsNotUsed(), "placed by no node, or placed degenerately");
    if (flattener.hiddenTriangles() > 0) {
        const std::string hidden = std::to_string(flattener.hiddenTriangles()) +
                                   " triangles left out: their material's alpha hides them (alphaMode MASK below "
                                   "alphaCutoff, or BLEND at alpha 0)";
        if (imported.mesh.indices.empty()) return import::errorIn(name, "no triangles to render: " + hidden);
        imported.report.warnings.push_back(hidden);
    }
    if (Status s = finalizeMesh(name, options, imported); !s.isOk()) return s;
    return imported;
}

}  // namespace

Result<ImportedMesh> importGltf(const std::string& path, const ImportOptions& options) {
    return import::guarded(path, [&]() -> Result<ImportedMesh> { return importGltfUnguarded(path, options); });
}

}  // namespace vastray

// glTF importer on hand-built files: node hierarchy, TRS, mirroring, primitive modes,
// index widths, data: URIs, materials, GLB container and KHR_draco_mesh_compression.
#include "DracoTestFile.h"
#include "ImportTestFiles.h"

namespace vastray::test {
namespace {

// A right triangle in the z=0 plane, counter-clockwise seen from +z.
const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

// Normal (z component of the cross product) of triangle t: tells the winding.
float windingZ(const TriangleMesh& m, size_t t) {
    const Vec3f a = m.positions[m.indices[t * 3]], b = m.positions[m.indices[t * 3 + 1]],
                c = m.positions[m.indices[t * 3 + 2]];
    const Vec3f u = b - a, v = c - a;
    return u.x * v.y - u.y * v.x;
}

TEST(GltfImport, HierarchyTrsAndMirrorKeepFrontFaces) {
    GltfBuilder b;
    b.addPositions(kTriangle);
    // Node 0 (translate x+10) has child 1 (scale 2) ; node 2 mirrors x (scale -1) and
    // reuses mesh 0: instancing must give two copies.
    const std::string json = b.json(
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
           "nodes":[{"translation":[10,0,0],"children":[1]},{"scale":[2,2,2],"mesh":0},
                    {"matrix":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1],"mesh":0}],
           "scenes":[{"nodes":[0,2]}],"scene":0)");
    auto r = importGltf(writeFile("tree.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.triangleCount(), 2u);
    EXPECT_EQ(r->mesh.positions[1], (Vec3f{12, 0, 0}));  // 10 + 2 * 1
    EXPECT_EQ(r->mesh.positions[4], (Vec3f{-1, 0, 0}));
    EXPECT_GT(windingZ(r->mesh, 0), 0.0f);
    EXPECT_GT(windingZ(r->mesh, 1), 0.0f) << "mirrored instance must keep its front face toward +z";
    EXPECT_EQ(r->report.format, "gltf");
}

TEST(GltfImport, RotationQuaternionIsApplied) {
    GltfBuilder b;
    b.addPositions(kTriangle);
    // 90 degrees about z: (1,0,0) -> (0,1,0). Tolerance 1e-6: float rounding of sin/cos.
    const std::string json = b.json(
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
           "nodes":[{"rotation":[0,0,0.7071067811865476,0.7071067811865476],"mesh":0}],"scenes":[{"nodes":[0]}])");
    auto r = importGltf(writeFile("rotate.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_NEAR(r->mesh.positions[1].x, 0.0f, 1e-6);
    EXPECT_NEAR(r->mesh.positions[1].y, 1.0f, 1e-6);
}

TEST(GltfImport, StripFanAndIndexWidths) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    b.addIndices<uint8_t>({0, 1, 2, 3});
    b.addIndices<uint16_t>({0, 1, 3, 2});
    b.addIndices<uint32_t>({0, 1, 3});
    const std::string json = b.json(
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":5},
                                    {"attributes":{"POSITION":0},"indices":2,"mode":6},
                                    {"attributes":{"POSITION":0},"indices":3,"mode":4},
                                    {"attributes":{"POSITION":0},"mode":1}]}],
           "nodes":[{"mesh":0}])");  // no scenes: every root node is drawn
    auto r = importGltf(writeFile("modes.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.triangleCount(), 5u);  // strip 2 + fan 2 + list 1; lines skipped
    EXPECT_EQ(r->report.primitivesSkipped, 1u);
    for (size_t t = 0; t < r->mesh.triangleCount(); ++t) EXPECT_GT(windingZ(r->mesh, t), 0.0f) << "triangle " << t;
}

TEST(GltfImport, MaterialsFromFile) {
    GltfBuilder b;
    b.addPositions(kTriangle);
    const std::string json = b.json(
        R"("extensionsUsed":["KHR_materials_emissive_strength"],
           "materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.5,0.25,1,1]},"emissiveFactor":[1,0.5,0],
                         "extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}},"doubleSided":true}],
           "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0},{"attributes":{"POSITION":0}}]}],
           "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    auto r = importGltf(writeFile("materials.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.materials.size(), 2u);
    const Material& m = r->mesh.materials[0];
    EXPECT_EQ(m.baseColor, (std::array<float, 4>{0.5f, 0.25f, 1, 1}));
    EXPECT_EQ(m.emissive, (std::array<float, 3>{4, 2, 0}));
    EXPECT_TRUE(m.doubleSided);
    EXPECT_FALSE(r->mesh.materials[1].doubleSided);  // glTF default material is single-sided
    EXPECT_EQ(r->mesh.materialIds, (std::vector<uint32_t>{0, 1}));
}

// Metallic-roughness factors (tinygltf's defaults 1 and 1 where absent), KHR_materials_specular's
// factor, the default material's metallic 1 and roughness 1 (spec 3.9.6); out of range refused.
TEST(GltfImport, MetallicRoughnessFactors) {
    GltfBuilder b;
    b.addPositions(kTriangle);
    const std::string json = b.json(
        R"("extensionsUsed":["KHR_materials_specular"],
           "materials":[{"pbrMetallicRoughness":{"metallicFactor":0.25,"roughnessFactor":0.5},
                         "extensions":{"KHR_materials_specular":{"specularFactor":0.75}}},
                        {"pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1]}}],
           "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0},{"attributes":{"POSITION":0},"material":1},
                                    {"attributes":{"POSITION":0}}]}],
           "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
    auto r = importGltf(writeFile("metallic.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    ASSERT_EQ(r->mesh.materials.size(), 3u);
    const Material& m = r->mesh.materials[0];
    EXPECT_EQ(m.metallic, 0.25f);
    EXPECT_EQ(m.roughness, 0.5f);
    EXPECT_EQ(m.specular, 0.75f);
    for (const Material& d : {r->mesh.materials[1], r->mesh.materials[2]}) {
        EXPECT_EQ(d.metallic, 1.0f) << d.name;
        EXPECT_EQ(d.roughness, 1.0f) << d.name;
        EXPECT_EQ(d.specular, 1.0f) << d.name;
    }
    for (const auto& [field, expected] :
         {std::pair{R"("pbrMetallicRoughness":{"metallicFactor":1.5})", "metallic 1.5 is outside [0, 1]"},
          std::pair{R"("pbrMetallicRoughness":{"roughnessFactor":-1})", "roughness -1 is outside [0, 1]"},
          std::pair{R"("extensions":{"KHR_materials_specular":{"specularFactor":1.25}})", "specular 1.25 is outside [0, 1]"}}) {
        GltfBuilder bad;
        bad.addPositions(kTriangle);
        const std::string text = bad.json(std::string(R"("materials":[{"name":"shiny",)") + field + R"(}],
           "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
        auto refused = importGltf(writeFile("badfactor.gltf", text));
        ASSERT_FALSE(refused.isOk()) << field;
        EXPECT_NE(refused.message().find(std::string("material 0 ('shiny'): ") + expected), std::string::npos)
            << refused.message();
    }
}

// A triangle drawn twice: with material 0 (`name`, whose extensions hold `extension`: `value`)
// and with material 1 (`other`, without it). The extension is used, and required when `required`.
std::string extensionMaterialGltf(const std::string& extension, const std::string& name, const std::string& value,
                                  const std::string& other, bool required) {
    GltfBuilder b;
    b.addPositions(kTriangle);
    const std::string listed = "[\"" + extension + "\"]";
    return b.json(R"("extensionsUsed":)" + listed + (required ? R"(,"extensionsRequired":)" + listed : "") +
                  R"(,"materials":[{"name":")" + name + R"(","extensions":{")" + extension + R"(":)" + value +
                  R"(}},{"name":")" + other + R"("}],
           "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0},{"attributes":{"POSITION":0},"material":1}]}],
           "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])");
}

// KHR_materials_specular's specularColorFactor (white without it); a value outside [0, 1000]
// is refused naming the material, a value of the wrong JSON type naming its JSON path.
TEST(GltfImport, SpecularColourFactor) {
    const auto document = [](const std::string& specular) {
        return extensionMaterialGltf("KHR_materials_specular", "tinted", specular, "plain", false);
    };
    auto r = importGltf(writeFile("specularcolour.gltf", document(R"({"specularFactor":0.5,"specularColorFactor":[0.25,1,24.5]})")));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.materials[0].specular, 0.5f);
    EXPECT_EQ(r->mesh.materials[0].specularColor, (std::array<float, 3>{0.25f, 1, 24.5f}));
    EXPECT_EQ(r->mesh.materials[1].specularColor, (std::array<float, 3>{1, 1, 1}));
    for (const auto& [specular, expected] :
         {std::pair{R"({"specularColorFactor":[-1,0,0]})", "material 0 ('tinted'): specular colour (-1, 0, 0) is outside [0, 1000]"},
          std::pair{R"({"specularColorFactor":[0,1000.5,0]})",
                    "material 0 ('tinted'): specular colour (0, 1000.5, 0) is outside [0, 1000]"},
          std::pair{R"({"specularColorFactor":[1e40,0,0]})", "material 0 ('tinted'): specular colour (inf, 0, 0) is outside [0, 1000]"},
          std::pair{R"({"specularColorFactor":["NaN",0,0]})",
                    R"(JSON /materials/0/extensions/KHR_materials_specular/specularColorFactor/0: expected a number, found string "NaN")"},
          std::pair{R"({"specularColorFactor":[1,1]})",
                    "JSON /materials/0/extensions/KHR_materials_specular/specularColorFactor: expected 3 numbers, found 2"},
          std::pair{R"({"specularColorFactor":0.5})",
                    "JSON /materials/0/extensions/KHR_materials_specular/specularColorFactor: expected an array of numbers, found number 0.5"},
          std::pair{R"({"specularFactor":"high"})",
                    R"(JSON /materials/0/extensions/KHR_materials_specular/specularFactor: expected a number, found string "high")"}}) {
        auto refused = importGltf(writeFile("badspecular.gltf", document(specular)));
        ASSERT_FALSE(refused.isOk()) << specular;
        EXPECT_NE(refused.message().find(expected), std::string::npos) << refused.message();
    }
}

// KHR_materials_clearcoat's factors (no coat without it); a factor outside [0, 1] is refused
// naming the material, a value of the wrong JSON type naming its JSON path; its normal texture
// (not read: the coat takes the surface's shading normal) is warned about once.
// Vertex attributes the package does not carry are warned about once per name: TANGENT (normal
// maps take their frames from the UVs), custom attributes; POSITION, NORMAL and COLOR_0 are
// carried, skins' JOINTS_n/WEIGHTS_n are the skins' warning, and UV sets without a texture map
// Import.cpp's "texture coordinates" one.
TEST(GltfImport, VertexAttributesNotCarriedAreWarnedOncePerName) {
    GltfBuilder b;
    const int pos = b.addPositions(kTriangle);
    const std::string p = std::to_string(pos);
    const std::string path = writeFile("attributes.gltf", b.json(R"("meshes":[{"primitives":[
        {"attributes":{"POSITION":)" + p + R"(,"TANGENT":)" + p + R"(,"TEXCOORD_1":)" + p + R"(,"_TEMPERATURE":)" + p +
                                                                   R"(,"JOINTS_0":)" + p + R"(}},
        {"attributes":{"POSITION":)" + p + R"(,"TANGENT":)" + p + R"(,"TEXCOORD_0":)" + p + R"(}}]}],
        "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])"));
    auto r = importGltf(path);
    ASSERT_TRUE(r.isOk()) << r.message();
    auto count = [&](const std::string& text) {
        return std::count_if(r->report.warnings.begin(), r->report.warnings.end(),
                             [&](const std::string& w) { return w.find(text) != std::string::npos; });
    };
    EXPECT_EQ(count("2 primitives' TANGENT attributes read but not used (normal maps take their frames from the UVs"), 1);
    EXPECT_EQ(count("1 primitives' _TEMPERATURE attributes read but not used"), 1);
    EXPECT_EQ(count("JOINTS_0"), 0);
    EXPECT_EQ(count("TEXCOORD_"), 0) << "no material has a texture: Import.cpp's warning covers every UV set";
    EXPECT_EQ(count("POSITION"), 0);
}

// Material extensions without a model in the renderer are warned about once per extension name
// (a glass rendered opaque is not a surprise), at most eight by name. Alpha: a material whose
// alpha hides it (MASK below its cutoff, BLEND at 0) has its triangles left out, whatever a texture
// would say; an untextured MASK above its cutoff is exactly opaque; a BLEND with some alpha
// blends (Material::alphaBlend) and is not warned about.
TEST(GltfImport, UnsupportedMaterialExtensionsAndAlphaModesAreWarnedOncePerKind) {
    GltfBuilder b;
    b.addPositions(kTriangle);
    std::string many;
    for (int i = 0; i < 10; ++i) many += ",\"EXT_made_up_" + std::to_string(i) + "\":{}";
    std::string primitives;
    for (int m = 0; m < 5; ++m)
        primitives += std::string(m ? "," : "") + R"({"attributes":{"POSITION":0},"material":)" + std::to_string(m) + "}";
    const std::string path = writeFile("unsupported.gltf", b.json(R"("extensionsUsed":["KHR_materials_transmission"],
       "materials":[{"name":"glass","alphaMode":"BLEND","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.3]},
                     "extensions":{"KHR_materials_transmission":{"transmissionFactor":1},
                                   "KHR_materials_specular":{"specularFactor":0.5}}},
                    {"name":"glass2","alphaMode":"MASK","extensions":{"KHR_materials_transmission":{})" + many + R"(}},
                    {"name":"plain","alphaMode":"OPAQUE"},
                    {"name":"hidden","alphaMode":"MASK","alphaCutoff":0.25,"pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.2]}},
                    {"name":"gone","alphaMode":"BLEND","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0]}}],
       "meshes":[{"primitives":[)" + primitives + R"(]}],
       "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])"));
    auto r = importGltf(path);
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.triangleCount(), 3u) << "the hidden and gone materials' triangles are left out";
    for (uint64_t t = 0; t < r->mesh.triangleCount(); ++t) EXPECT_LT(r->mesh.materialOf(t), 3u);
    auto count = [&](const std::string& text) {
        return std::count_if(r->report.warnings.begin(), r->report.warnings.end(),
                             [&](const std::string& w) { return w.find(text) != std::string::npos; });
    };
    EXPECT_EQ(count("2 materials' KHR_materials_transmission extensions read but not used"), 1);
    EXPECT_EQ(count("KHR_materials_specular"), 0) << "specular is rendered";
    EXPECT_EQ(count("alphaMode BLEND"), 0) << "BLEND blends";
    EXPECT_EQ(count("read but not used (rendered opaque)"), 0) << "the untextured MASK above its cutoff is exactly opaque";
    ASSERT_EQ(r->mesh.materials[0].name, "glass");
    EXPECT_TRUE(r->mesh.materials[0].alphaBlend);
    EXPECT_EQ(r->mesh.materials[0].baseColor[3], 0.3f);
    EXPECT_FALSE(r->mesh.materials[1].alphaBlend) << "MASK";
    for (const Material& m : r->mesh.materials) EXPECT_EQ(m.alphaCutoff, 0.0f) << m.name << ": no base colour map";
    EXPECT_EQ(count("2 triangles left out: their material's alpha hides them"), 1);
    EXPECT_EQ(count("materials' EXT_made_up_"), 7) << "eight names at most, transmission among them";
    EXPECT_EQ(count("3 other material extensions read but not used"), 1);

    GltfBuilder only;
    only.addPositions(kTriangle);
    auto none = importGltf(writeFile("all-hidden.gltf", only.json(R"(
       "materials":[{"name":"hidden","alphaMode":"MASK","pbrMetallicRoughness":{"baseColorFactor":[1,1,1,0.2]}}],
       "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],"nodes":[{"mesh":0}],
       "scenes":[{"nodes":[0]}])")));
    ASSERT_FALSE(none.isOk());
    EXPECT_EQ(none.message(), "all-hidden.gltf: no triangles to render: 1 triangles left out: their material's alpha "
                              "hides them (alphaMode MASK below alphaCutoff, or BLEND at alpha 0)");
}

// KHR_materials_ior: the index of refraction reaches the material (1.5 without it, 0 accepted as
// the extension allows); outside 0 and [1, 1000] it is refused naming the material, a value of
// the wrong JSON type naming its JSON path; the extension is not warned about as unused.
TEST(GltfImport, IorReachesTheMaterial) {
    const auto document = [](const std::string& ior) {
        return extensionMaterialGltf("KHR_materials_ior", "glass", ior, "plain", true);
    };
    for (const auto& [ior, expected] : {std::pair{R"({"ior":2.25})", 2.25f}, std::pair{R"({"ior":0})", 0.0f},
                                        std::pair{R"({})", 1.5f}}) {
        auto r = importGltf(writeFile("ior.gltf", document(ior)));
        ASSERT_TRUE(r.isOk()) << r.message();
        EXPECT_EQ(r->mesh.materials[0].ior, expected) << ior;
        EXPECT_EQ(r->mesh.materials[1].ior, 1.5f);
        for (const std::string& w : r->report.warnings) EXPECT_EQ(w.find("KHR_materials_ior"), std::string::npos) << w;
    }
    for (const auto& [ior, expected] :
         {std::pair{R"({"ior":0.5})", "material 0 ('glass'): ior 0.5 is neither 0 nor in [1, 1000]"},
          std::pair{R"({"ior":1e9})", "material 0 ('glass'): ior 1e+09 is neither 0 nor in [1, 1000]"},
          std::pair{R"({"ior":"high"})",
                    R"(JSON /materials/0/extensions/KHR_materials_ior/ior: expected a number, found string "high")"}}) {
        auto refused = importGltf(writeFile("badior.gltf", document(ior)));
        ASSERT_FALSE(refused.isOk()) << ior;
        EXPECT_NE(refused.message().find(expected), std::string::npos) << refused.message();
    }
}

TEST(GltfImport, ClearcoatFactors) {
    const auto document = [](const std::string& coat) {
        return extensionMaterialGltf("KHR_materials_clearcoat", "lacquer", coat, "bare", true);
    };
    auto r = importGltf(writeFile("clearcoat.gltf", document(R"({"clearcoatFactor":0.75,"clearcoatRoughnessFactor":0.125,
        "clearcoatNormalTexture":{"index":0}})")));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.materials[0].clearcoat, 0.75f);
    EXPECT_EQ(r->mesh.materials[0].clearcoatRoughness, 0.125f);
    EXPECT_EQ(r->mesh.materials[1].clearcoat, 0.0f);
    EXPECT_EQ(r->mesh.materials[1].clearcoatRoughness, 0.0f);
    size_t coatWarnings = 0;
    for (const std::string& w : r->report.warnings)
        if (w.find("KHR_materials_clearcoat normal textures") != std::string::npos) {
            ++coatWarnings;
            EXPECT_NE(w.find("1 "), std::string::npos) << w;
        }
    EXPECT_EQ(coatWarnings, 1u);
    auto plain = importGltf(writeFile("clearcoat-plain.gltf", document(R"({"clearcoatFactor":1})")));
    ASSERT_TRUE(plain.isOk()) << plain.message();
    EXPECT_EQ(plain->mesh.materials[0].clearcoat, 1.0f);
    EXPECT_EQ(plain->mesh.materials[0].clearcoatRoughness, 0.0f);
    for (const auto& [coat, expected] :
         {std::pair{R"({"clearcoatFactor":-0.5})", "material 0 ('lacquer'): clearcoat -0.5 is outside [0, 1]"},
          std::pair{R"({"clearcoatFactor":1,"clearcoatRoughnessFactor":1.5})",
                    "material 0 ('lacquer'): clearcoat roughness 1.5 is outside [0, 1]"},
          std::pair{R"({"clearcoatFactor":1e40})", "material 0 ('lacquer'): clearcoat inf is outside [0, 1]"},
          std::pair{R"({"clearcoatFactor":"NaN"})",
                    R"(JSON /materials/0/extensions/KHR_materials_clearcoat/clearcoatFactor: expected a number, found string "NaN")"},
          std::pair{R"({"clearcoatRoughnessFactor":[0.5]})",
                    "JSON /materials/0/extensions/KHR_materials_clearcoat/clearcoatRoughnessFactor: expected a number, found array [0.5]"},
          std::pair{R"({"clearcoatTexture":3})",
                    "JSON /materials/0/extensions/KHR_materials_clearcoat/clearcoatTexture: expected an object, found number 3"}}) {
        auto refused = importGltf(writeFile("badclearcoat.gltf", document(coat)));
        ASSERT_FALSE(refused.isOk()) << coat;
        EXPECT_NE(refused.message().find(expected), std::string::npos) << refused.message();
    }
}

TEST(GltfImport, GlbWithBinChunk) {
    std::string bin;
    for (float f : kTriangle) appendRaw(bin, f);
    const std::string json =
        R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36}],"bufferViews":[{"buffer":0,"byteLength":36}],
            "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3}],
            "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})";
    auto r = importMesh(writeFile("tri.GLB", glb(json, bin)));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->report.format, "glb");
    EXPECT_EQ(r->mesh.triangleCount(), 1u);
}

TEST(GltfImport, ExternalBufferInsideTheModelFolderLoads) {
    std::string bin;
    for (float f : kTriangle) appendRaw(bin, f);
    std::filesystem::create_directories(tmpPath("sub"));
    writeFile("sub/tri.bin", bin);
    const std::string json =
        R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"sub/tri.bin"}],
            "bufferViews":[{"buffer":0,"byteLength":36}],
            "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3}],
            "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}]})";
    auto r = importGltf(writeFile("external.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.triangleCount(), 1u);
}

TEST(GltfImport, DracoCompressedPrimitiveDecodes) {
    const std::string json = dracoGridGltf(4);
    auto r = importGltf(writeFile("draco.gltf", json));
    ASSERT_TRUE(r.isOk()) << r.message();
    EXPECT_EQ(r->mesh.triangleCount(), 32u);
    const Aabb box = r->mesh.bounds();
    EXPECT_EQ(box.lo, (Vec3f{0, 0, 0}));  // lossless: exact
    EXPECT_EQ(box.hi, (Vec3f{4, 4, 0}));
}

}  // namespace
}  // namespace vastray::test

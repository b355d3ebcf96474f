// The command line as a user drives it: exit codes, messages, files.
#include "CliTestSupport.h"
#include "CommandRunner.h"
#include "TestTmp.h"
#include "vastray/core/ImageFile.h"
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace {

using vastray::test::CommandResult;
using vastray::test::runVastray;
using vastray::test::slurp;

class Cli : public ::testing::Test {
protected:
    // A file in this suite's scratch folder.
    static std::string tmp(const std::string& name) {
        const std::filesystem::path dir = vastray::test::testTmpDir("cli");
        std::filesystem::create_directories(dir);
        return (dir / name).string();
    }
    static void SetUpTestSuite() {
        CommandResult g = runVastray("generate terrain --triangles 20000 --seed 4 -o " + tmp("terrain.ply"));
        ASSERT_EQ(g.exitCode, 0) << g.output;
        CommandResult i = runVastray("import " + tmp("terrain.ply") + " -o " + tmp("terrain.vast") + " --chunk-size 64KiB --progress lines");
        ASSERT_EQ(i.exitCode, 0) << i.output;
    }
};

TEST_F(Cli, ImportPrintsProgressLinesWithoutATerminal) {
    CommandResult i = runVastray("import " + tmp("terrain.ply") + " -o " + tmp("again.vast") + " --chunk-size 64KiB");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    EXPECT_NE(i.output.find("import: 100%"), std::string::npos) << i.output;
    EXPECT_EQ(i.output.find('\r'), std::string::npos) << "no bar redraws in a log";
}

TEST_F(Cli, InfoJsonHasTheDocumentedFields) {
    CommandResult r = runVastray("info " + tmp("terrain.vast") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* key : {"\"triangles\"", "\"chunks\"", "\"chunk_size_bytes\": 65536", "\"max_chunk_resident_bytes\"",
                            "\"bounds\"", "\"min\"", "\"max\"", "\"file_bytes\"", "\"duplicated_references\"",
                            "\"quantize_bits\": 20", "\"chunk\"", "\"offset\"", "\"size\"", "\"resident_bytes\"",
                            "\"codec\": \"draco\""})
        EXPECT_NE(r.output.find(key), std::string::npos) << key;
}

// glTF material extensions (KHR_materials_specular's colour, KHR_materials_clearcoat,
// KHR_materials_ior) reach the package and `info --json` lists them per material; the coat's normal texture (not read) is
// warned about.
TEST_F(Cli, InfoJsonListsTheMaterialExtensions) {
    // One triangle (0,0,0), (1,0,0), (0,1,0) as base64 floats.
    const std::string gltf = R"({"asset":{"version":"2.0"},
        "extensionsUsed":["KHR_materials_specular","KHR_materials_clearcoat","KHR_materials_ior"],
        "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
        "bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
        "materials":[{"name":"lacquer","extensions":{"KHR_materials_specular":{"specularColorFactor":[0.5,1,2]},
            "KHR_materials_clearcoat":{"clearcoatFactor":0.75,"clearcoatRoughnessFactor":0.125,"clearcoatNormalTexture":{"index":0}},
            "KHR_materials_ior":{"ior":1.25}}}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]})";
    std::ofstream(tmp("coat.gltf")) << gltf;
    CommandResult i =
        runVastray("import " + tmp("coat.gltf") + " -o " + tmp("coat.vast") + " --progress none");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    EXPECT_NE(i.output.find("1 KHR_materials_clearcoat normal textures read but not used"), std::string::npos) << i.output;
    CommandResult r = runVastray("info " + tmp("coat.vast") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    for (const char* key : {"\"name\": \"lacquer\"", "\"specular_color\"", "0.5", "2.0", "\"clearcoat\": 0.75",
                            "\"clearcoat_roughness\": 0.125", "\"ior\": 1.25"})
        EXPECT_NE(r.output.find(key), std::string::npos) << key << " in " << r.output;
}

// BoxTextured made a cut-out (alphaMode MASK, cutoff 0.3; its texture is opaque, so nothing is cut):
// import warns of nothing, info counts the cut-out in text and gives its cutoff in JSON.
TEST_F(Cli, InfoCountsAlphaCutouts) {
    const std::filesystem::path box = "/usr/share/assimp/models/glTF2/BoxTextured-glTF";
    if (!std::filesystem::exists(box)) GTEST_SKIP() << box << " is absent (assimp-testmodels not installed)";
    const std::filesystem::path dir = tmp("masked-box");
    std::filesystem::create_directories(dir);
    for (const char* f : {"BoxTextured0.bin", "CesiumLogoFlat.png"})
        std::filesystem::copy_file(box / f, dir / f, std::filesystem::copy_options::overwrite_existing);
    std::ifstream in(box / "BoxTextured.gltf");
    std::string gltf{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const std::string name = "\"name\": \"Texture\"";
    ASSERT_NE(gltf.find(name), std::string::npos);
    gltf.replace(gltf.find(name), name.size(), name + ", \"alphaMode\": \"MASK\", \"alphaCutoff\": 0.3");
    std::ofstream((dir / "masked.gltf").string()) << gltf;
    CommandResult i = runVastray("import " + (dir / "masked.gltf").string() + " -o " + tmp("masked.vast") + " --progress none");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    EXPECT_EQ(i.output.find("MASK"), std::string::npos) << i.output;
    CommandResult text = runVastray("info " + tmp("masked.vast"));
    ASSERT_EQ(text.exitCode, 0) << text.output;
    EXPECT_NE(text.output.find("materials            1 (1 alpha cut-outs)"), std::string::npos) << text.output;
    CommandResult json = runVastray("info " + tmp("masked.vast") + " --json");
    ASSERT_EQ(json.exitCode, 0) << json.output;
    EXPECT_NE(json.output.find("\"alpha_cutoff\": 0.30000001192092896"), std::string::npos) << json.output;
}

// A textured glTF (Debian's assimp-testmodels BoxTextured): import stores its texture, info lists
// it in text and JSON with the material's map; vulkan and embree renders (both sample it) say
// nothing of it.
TEST_F(Cli, TexturedGltfStoresItsTextureAndInfoListsIt) {
    const std::string file = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is absent (assimp-testmodels not installed)";
    CommandResult i = runVastray("import " + file + " -o " + tmp("box.vast") + " --progress none");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    EXPECT_NE(i.output.find("textures: 1 (11 pages of 128 x 128 texels"), std::string::npos) << i.output;
    CommandResult text = runVastray("info " + tmp("box.vast"));
    ASSERT_EQ(text.exitCode, 0) << text.output;
    EXPECT_NE(text.output.find("vastray package v16"), std::string::npos) << text.output;
    EXPECT_NE(text.output.find("'image 0 ('CesiumLogoFlat.png') of BoxTextured.gltf': 211 x 211 texels, 8 levels, 11 pages"),
              std::string::npos)
        << text.output;
    CommandResult json = runVastray("info " + tmp("box.vast") + " --json");
    ASSERT_EQ(json.exitCode, 0) << json.output;
    for (const char* key : {"\"textures\"", "\"baseColorTexture\"", "\"wrap\"", "\"mirror\"", "\"stored_bytes\""})
        EXPECT_NE(json.output.find(key), std::string::npos) << key << " in " << json.output;
    CommandResult r = runVastray("render " + tmp("box.vast") + " -o " + tmp("box.png") +
                                 " --backend vulkan --resolution 16x16 --spp 1 --progress none");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("note:"), std::string::npos) << "the vulkan backend renders its base colour map: " << r.output;
    CommandResult e = runVastray("render " + tmp("box.vast") + " -o " + tmp("box-embree.png") +
                                 " --backend embree --resolution 16x16 --spp 1 --progress none");
    ASSERT_EQ(e.exitCode, 0) << e.output;
    EXPECT_EQ(e.output.find("note:"), std::string::npos) << "the embree backend renders its base colour map: " << e.output;
}

// A glTF quad with UVs whose material reads a normal map and, in the second file, an occlusion
// map too: both backends render normal maps without a word, and import and both backends say
// that occlusion maps are stored but not applied, by design (docs/RENDERING.md, "Normal maps").
TEST_F(Cli, NormalMapsRenderAndOcclusionMapsAreSaidNotApplied) {
    ASSERT_TRUE(vastray::writeRgba8Png(tmp("bumps.png"), 2, 2, std::vector<uint8_t>(2 * 2 * 4, 200)).isOk());
    auto quad = [](const std::string& maps) {
        return R"({"asset":{"version":"2.0"},
 "buffers":[{"byteLength":92,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAIA/AACAPwAAgD8AAAAAAAAAAAAAAAAAAAEAAgAAAAIAAwA="}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":32},
                {"buffer":0,"byteOffset":80,"byteLength":12}],
 "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":4,"min":[0,0,0],"max":[1,1,0]},
              {"bufferView":1,"componentType":5126,"type":"VEC2","count":4},
              {"bufferView":2,"componentType":5123,"type":"SCALAR","count":6}],
 "images":[{"uri":"bumps.png"}], "textures":[{"source":0}],
 "materials":[{)" + maps + R"(}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2,"material":0}]}],
 "nodes":[{"mesh":0}]})";
    };
    std::ofstream(tmp("normal-mapped.gltf")) << quad(R"("normalTexture":{"index":0,"scale":0.5})");
    std::ofstream(tmp("occluded.gltf")) << quad(R"("normalTexture":{"index":0},"occlusionTexture":{"index":0})");
    for (const char* name : {"normal-mapped", "occluded"}) {
        const std::string package = tmp(std::string(name) + ".vast");
        CommandResult i = runVastray("import " + tmp(std::string(name) + ".gltf") + " -o " + package + " --progress none");
        ASSERT_EQ(i.exitCode, 0) << i.output;
        const bool occluded = std::string(name) == "occluded";
        EXPECT_EQ(i.output.find("occlusion maps: stored, not applied by design") != std::string::npos, occluded)
            << i.output;
        for (const char* backend : {"embree", "vulkan"}) {
            CommandResult e = runVastray("render " + package + " -o " +
                                         tmp(std::string(name) + backend + ".png") + " --backend " + backend +
                                         " --resolution 16x16 --spp 1 --progress none");
            ASSERT_EQ(e.exitCode, 0) << e.output;
            if (!occluded) {
                EXPECT_EQ(e.output.find("note:"), std::string::npos) << backend << " renders normal maps: " << e.output;
            } else {
                EXPECT_NE(e.output.find("1 material of " + package + " read occlusion maps, which are stored but not "
                                        "applied, by design"),
                          std::string::npos)
                    << backend << ": " << e.output;
            }
        }
    }
}

// An FBX through assimp whose diffuse map is a PNG the file embeds: import stores it, info
// lists it by the embedded image's name.
TEST_F(Cli, AssimpEmbeddedTextureIsStoredAndInfoListsIt) {
    const std::string file = "/usr/share/assimp/models/FBX/embedded_ascii/box.FBX";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is absent (assimp-testmodels not installed)";
    CommandResult i = runVastray("import " + file + " -o " + tmp("fbx-box.vast") + " --progress none");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    CommandResult info = runVastray("info " + tmp("fbx-box.vast"));
    ASSERT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("uv_test.png') of box.FBX': 512 x 512 texels"), std::string::npos) << info.output;
}

// info says how the device keeps positions: 8 bytes a vertex on the import's grid of 20 bits
// (QuantizationGrid::packsPositions), 12 with more bits or lossless.
TEST_F(Cli, InfoSaysHowTheDeviceKeepsPositions) {
    CommandResult text = runVastray("info " + tmp("terrain.vast"));
    EXPECT_NE(text.output.find("20 bits, step"), std::string::npos) << text.output;
    EXPECT_NE(text.output.find("(device positions: 8 bytes a vertex)"), std::string::npos) << text.output;
    EXPECT_NE(
        runVastray("info " + tmp("terrain.vast") + " --json").output.find("\"device_position_bytes\": 8"),
        std::string::npos);
    for (const char* bits : {"22", "0"}) {
        const std::string package = tmp(std::string("terrain-") + bits + ".vast");
        CommandResult i = runVastray("import " + tmp("terrain.ply") + " -o " + package + " --quantize-bits " +
                                     bits + " --progress none");
        ASSERT_EQ(i.exitCode, 0) << i.output;
        CommandResult info = runVastray("info " + package + " --json");
        EXPECT_NE(info.output.find("\"device_position_bytes\": 12"), std::string::npos) << bits << ": " << info.output;
    }
}

// A textured OBJ (vt, and an MTL map_Kd of a PNG beside it): the package stores the texture and
// info lists it, says the package has texture coordinates, in text and JSON, and both backends
// render the uv AOV into an EXR (its values: UvRender.*).
TEST_F(Cli, TexturedObjKeepsUvsAndRendersTheUvAov) {
    std::ofstream(tmp("textured.obj")) << "mtllib textured.mtl\nusemtl painted\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                          "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvn 0 0 1\n"
                                          "f 1/1/1 2/2/1 3/3/1\nf 2/2/1 4/4/1 3/3/1\n";
    std::ofstream(tmp("textured.mtl")) << "newmtl painted\nKd 1 1 1\nmap_Kd -s 2 2 wood.png\n";
    ASSERT_TRUE(vastray::writeRgba8Png(tmp("wood.png"), 4, 2, std::vector<uint8_t>(4 * 2 * 4, 200)).isOk());
    CommandResult i = runVastray("import " + tmp("textured.obj") + " -o " + tmp("textured.vast") + " --progress none");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    CommandResult info = runVastray("info " + tmp("textured.vast"));
    EXPECT_NE(info.output.find("'wood.png' of textured.obj': 4 x 2 texels"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("vertex attributes    shading normals, texture coordinates"), std::string::npos) << info.output;
    EXPECT_NE(runVastray("info " + tmp("textured.vast") + " --json").output.find("\"vertex_uvs\": true"), std::string::npos);
    EXPECT_NE(runVastray("info " + tmp("terrain.vast") + " --json").output.find("\"vertex_uvs\": false"), std::string::npos);
    for (const char* backend : {"embree", "vulkan"}) {
        CommandResult r = runVastray("render " + tmp("textured.vast") + " --backend " + backend +
                                     " --resolution 16x16 --spp 1 --aovs uv --progress none -o " +
                                     tmp("uv.exr"));
        EXPECT_EQ(r.exitCode, 0) << backend << ": " << r.output;
        EXPECT_TRUE(std::filesystem::exists(tmp("uv.exr"))) << backend;
        std::filesystem::remove(tmp("uv.exr"));
    }
}

TEST_F(Cli, MeshoptCodecImportsVerifiesAndSaysSo) {
    CommandResult i = runVastray("import " + tmp("terrain.ply") + " -o " + tmp("meshopt.vast") +
                                 " --chunk-size 64KiB --codec meshopt --progress none");
    ASSERT_EQ(i.exitCode, 0) << i.output;
    EXPECT_NE(i.output.find("meshopt encode"), std::string::npos) << i.output;
    CommandResult info = runVastray("info " + tmp("meshopt.vast") + " --verify");
    ASSERT_EQ(info.exitCode, 0) << info.output;
    EXPECT_NE(info.output.find("chunk codec          meshopt"), std::string::npos) << info.output;
    EXPECT_NE(runVastray("info " + tmp("meshopt.vast") + " --json").output.find("\"codec\": \"meshopt\""), std::string::npos);
}

TEST_F(Cli, VerifyNamesTheDamagedChunkAndFails) {
    ASSERT_EQ(runVastray("info " + tmp("terrain.vast") + " --verify").exitCode, 0);
    // Damage the last byte of the file: it belongs to the last chunk.
    std::filesystem::copy_file(tmp("terrain.vast"), tmp("damaged.vast"), std::filesystem::copy_options::overwrite_existing);
    {
        std::fstream f(tmp("damaged.vast"), std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(-1, std::ios::end);
        char c = 0;
        f.get(c);
        f.seekp(-1, std::ios::end);
        f.put(char(c ^ 0x40));
    }
    CommandResult r = runVastray("info " + tmp("damaged.vast") + " --verify");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find(": checksum mismatch"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("1 of "), std::string::npos) << r.output;
}

TEST_F(Cli, ExportCellsWritesOneBoxPerCell) {
    CommandResult r =
        runVastray("info " + tmp("terrain.vast") + " --json --export-cells " + tmp("cells.obj"));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string obj = slurp(tmp("cells.obj"));
    size_t objects = 0, vertices = 0;
    std::istringstream lines(obj);
    for (std::string line; std::getline(lines, line);) {
        objects += line.rfind("o ", 0) == 0;
        vertices += line.rfind("v ", 0) == 0;
    }
    EXPECT_GT(objects, 1u);
    EXPECT_EQ(vertices, objects * 8);
    EXPECT_NE(obj.find("o chunk_0\n"), std::string::npos);
    ASSERT_EQ(runVastray("info " + tmp("terrain.vast") + " --export-cells " + tmp("cells.ply")).exitCode, 0);
    EXPECT_NE(slurp(tmp("cells.ply")).find("property int chunk_id"), std::string::npos);
    CommandResult bad = runVastray("info " + tmp("terrain.vast") + " --export-cells " + tmp("cells.txt"));
    EXPECT_NE(bad.exitCode, 0);
    EXPECT_NE(bad.output.find("must end in .obj or .ply"), std::string::npos) << bad.output;
}

TEST_F(Cli, BadArgumentsAreClearErrors) {
    struct Case {
        std::string arguments, expected;
    } cases[] = {
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.vast") + " --chunk-size 12parsecs", "unknown unit"},
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.vast") + " --chunk-size 1KiB", "minimum"},
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.vast") + " --quantize-bits 31", "--quantize-bits"},
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.ply"), "must end in .vast"},
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.vast") + " --draco-speed 11", "--draco-speed must be 0..10"},
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.vast") + " --progress loud", "--progress"},
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.vast") + " --codec zstd", "--codec"},
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.vast") + " --resident-bytes-per-triangle -3",
         "--resident-bytes-per-triangle must be 0 (no cap) or positive"},
        {"import " + tmp("missing.ply") + " -o " + tmp("x.vast"), "missing.ply"},
        {"import " + tmp("terrain.ply") + " -o " + tmp("x.vast") + " --double-sided --single-sided", "excludes"},
        {"generate cube --triangles 100 -o " + tmp("x.ply"), "sphere"},
        {"generate sphere --triangles 100 -o " + tmp("x.txt"), "x.txt"},
        {"info " + tmp("terrain.ply"), "not a vastray package"},
    };
    for (const Case& c : cases) {
        CommandResult r = runVastray(c.arguments);
        EXPECT_NE(r.exitCode, 0) << c.arguments;
        EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.arguments << "\n" << r.output;
    }
    EXPECT_FALSE(std::filesystem::exists(tmp("x.vast")));
}

TEST_F(Cli, SizesAcceptBinarySuffixes) {
    CommandResult r = runVastray("import " + tmp("terrain.ply") + " -o " + tmp("big.vast") + " --chunk-size 1MiB --progress none");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(runVastray("info " + tmp("big.vast") + " --json").output.find("\"chunk_size_bytes\": 1048576"), std::string::npos);
}

TEST_F(Cli, HelpListsEveryCommand) {
    CommandResult r = runVastray("--help");
    EXPECT_EQ(r.exitCode, 0);
    for (const char* command : {"generate", "import", "info"}) EXPECT_NE(r.output.find(command), std::string::npos);
}

}  // namespace

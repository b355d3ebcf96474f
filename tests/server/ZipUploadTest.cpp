// Multi-file uploads: a zip holding a glTF with its .bin and images, or an OBJ with its .mtl,
// imported with every path kept inside the upload; hostile archives (zip-slip, absolute paths,
// symbolic links, too many entries, too many bytes, zip bombs) refused by name, leaving nothing
// behind. The archives are written with libzip (ZipWriter.h).
#include <grpcpp/grpcpp.h>

#include <random>

#include "GrpcUpload.h"
#include "ZipUploadSupport.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/v1/scene_service.grpc.pb.h"

namespace vastray::test {
namespace {

namespace fs = std::filesystem;

// A glTF quad (2 triangles) whose buffer and texture live in sub-folders of the archive.
std::string quadBin() {
    const float positions[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint16_t indices[] = {0, 1, 2, 0, 2, 3};
    std::string bin(reinterpret_cast<const char*>(positions), sizeof positions);
    bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
    return bin;
}

std::string quadGltf(const std::string& bufferUri) {
    return R"({"asset":{"version":"2.0"},
  "buffers":[{"byteLength":60,"uri":")" + bufferUri + R"("}],
  "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":12}],
  "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":4,"min":[0,0,0],"max":[1,1,0]},
               {"bufferView":1,"componentType":5123,"type":"SCALAR","count":6}],
  "images":[{"uri":"textures/albedo.png"}],"textures":[{"source":0}],
  "materials":[{"name":"painted","pbrMetallicRoughness":{"baseColorFactor":[0.2,0.4,0.6,1],
                "baseColorTexture":{"index":0}}}],
  "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],
  "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}],"scene":0})";
}

const char* kObj = "mtllib materials/red.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\nf 1 2 3\nf 1 3 4\n";
const char* kMtl = "newmtl red\nKd 0.9 0.1 0.05\n";

class ZipUploadTest : public ZipUploadServerTest {
protected:
    std::vector<Material> storedMaterials(const std::string& sceneId) {
        auto reader = PackageReader::open((dataDir() / "scenes" / (sceneId + ".vast")).string());
        EXPECT_TRUE(reader) << reader.message();
        return reader ? (*reader)->info().materials : std::vector<Material>{};
    }
};

TEST_F(ZipUploadTest, GltfWithItsBinAndTextureInFolders) {
    startServer();
    const fs::path zip = dir_ / "quad.zip";
    writeZip(zip, {{"model/", ""},
                   {"model/quad.gltf", quadGltf("buffers/quad.bin")},
                   {"model/buffers/quad.bin", quadBin()},
                   {"model/textures/albedo.png", "not decoded: textures are not carried into packages yet"},
                   {"__MACOSX/model/._quad.gltf", "Finder metadata, skipped"}});
    auto res = put(zip, "quad.zip");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
    const json scene = json::parse(res->body);
    EXPECT_EQ(scene["format"], "zip");
    EXPECT_EQ(scene["triangles"], "2");
    EXPECT_EQ(scene["upload_bytes"], std::to_string(fs::file_size(zip)));
    const auto materials = storedMaterials(scene["id"]);
    ASSERT_EQ(materials.size(), 1u);
    EXPECT_EQ(materials[0].name, "painted");
    EXPECT_FLOAT_EQ(materials[0].baseColor[2], 0.6f) << "the glTF's own material";
    EXPECT_TRUE(fs::is_empty(dataDir() / "tmp"));
    // The scene renders like any other.
    auto job = submit(smallJob(scene["id"]));
    ASSERT_EQ(job->status, 202) << job->body;
    waitForState(json::parse(job->body)["id"], "JOB_STATE_SUCCEEDED");
}

// A zip through gRPC's client stream, in several messages (imported there: gRPC goes first);
// HTTP then finds the same scene.
TEST_F(ZipUploadTest, GrpcUploadOfAZipImportsItToo) {
    startServer();
    const fs::path zip = dir_ / "red.zip";
    writeZip(zip, {{"red.obj", kObj}, {"materials/red.mtl", kMtl}});
    auto stub = v1::SceneService::NewStub(grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials()));
    v1::Scene scene;
    const grpc::Status status = uploadSceneOverGrpc(*stub, "red.zip", readBytes(zip), 100, false, &scene);
    ASSERT_TRUE(status.ok()) << status.error_message();
    EXPECT_EQ(scene.format(), "zip");
    EXPECT_EQ(scene.triangles(), 2u);
    EXPECT_FLOAT_EQ(storedMaterials(scene.id())[0].baseColor[0], 0.9f);
    auto viaHttp = put(zip, "red.zip");
    ASSERT_TRUE(viaHttp && viaHttp->status == 200) << (viaHttp ? viaHttp->body : "");
    EXPECT_EQ(json::parse(viaHttp->body)["id"], scene.id());
}

// The .mtl the OBJ names is read from the archive: its colour reaches the package (a plain
// .obj upload loses it).
TEST_F(ZipUploadTest, ObjWithItsMtl) {
    startServer();
    const fs::path zip = dir_ / "red.zip";
    writeZip(zip, {{"red.obj", kObj}, {"materials/red.mtl", kMtl}});
    auto res = put(zip, "red.zip");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
    const json scene = json::parse(res->body);
    EXPECT_EQ(scene["triangles"], "2");
    const auto materials = storedMaterials(scene["id"]);
    ASSERT_EQ(materials.size(), 1u);
    EXPECT_EQ(materials[0].name, "red");
    EXPECT_FLOAT_EQ(materials[0].baseColor[0], 0.9f);
    EXPECT_FLOAT_EQ(materials[0].baseColor[1], 0.1f);

    // Uploaded alone, the same OBJ has no library to read: the default colour.
    auto alone = http().Put("/v1/scenes?name=red.obj", std::string(kObj), "application/octet-stream");
    ASSERT_TRUE(alone && alone->status == 200) << (alone ? alone->body : "");
    EXPECT_NE(storedMaterials(json::parse(alone->body)["id"])[0].baseColor[0], 0.9f);
}

TEST_F(ZipUploadTest, PathsThatLeaveTheUploadAreRefusedByName) {
    startServer();
    expectZipRefused("slip", {{"../evil.obj", kObj}}, {"entry '../evil.obj'", "'..'"});
    expectZipRefused("deepslip", {{"a/b/../../../evil.obj", kObj}}, {"entry 'a/b/../../../evil.obj'", "'..'"});
    expectZipRefused("absolute", {{"/tmp/evil.obj", kObj}}, {"entry '/tmp/evil.obj'", "absolute path"});
    expectZipRefused("drive", {{"C:/evil.obj", kObj}}, {"entry 'C:/evil.obj'", "drive letter"});
    expectZipRefused("backslash", {{"..\\evil.obj", kObj}}, {"backslash"});
    expectZipRefused("link", {{"red.obj", kObj}, {"materials/red.mtl", "/etc/passwd", true}},
                     {"entry 'materials/red.mtl'", "symbolic link"});
    // A model that names a file outside its folder: refused by the importer, named by path.
    expectZipRefused("mtlslip", {{"m/red.obj", "mtllib ../../../../etc/passwd\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"}},
                     {"m/red.obj", "mtllib '../../../../etc/passwd'"});
    EXPECT_FALSE(fs::exists(dataDir() / "evil.obj"));
    EXPECT_FALSE(fs::exists(dataDir().parent_path() / "evil.obj"));
    EXPECT_FALSE(fs::exists("/tmp/evil.obj"));
}

TEST_F(ZipUploadTest, ArchivesWithoutExactlyOneModelAreRefused) {
    startServer();
    expectZipRefused("empty", {{"readme.txt", "no model here"}}, {"holds no model"});
    expectZipRefused("two", {{"a.obj", kObj}, {"b/c.gltf", quadGltf("c.bin")}}, {"holds 2 models", "a.obj", "b/c.gltf"});
    // Not a zip at all, though named one.
    auto res = http().Put("/v1/scenes?name=broken.zip", std::string("PK\x03\x04 garbage"), "application/zip");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400) << res->body;
    EXPECT_NE(res->body.find("broken.zip: not a readable zip archive"), std::string::npos) << res->body;
}

TEST_F(ZipUploadTest, BombsAndOversizedArchivesAreRefusedByTheirLimit) {
    startServer({"--max-upload", "2MiB"});
    // 8 MiB of zeros compress ~1000:1: refused while expanding, by ratio.
    expectZipRefused("bomb", {{"bomb.obj", std::string(8u << 20, '\0')}}, {"entry 'bomb.obj'", "expands more than 200 times"});
    // Random digits compress ~2:1, within the ratio, but 3 MiB exceed --max-upload (2 MiB).
    std::mt19937 random(17);
    std::string digits(3u << 20, '0');
    for (char& c : digits) c = char('0' + random() % 10);
    expectZipRefused("large", {{"large.obj", digits}}, {"expands to more than the limit of 2097152 bytes", "large.obj"});
    // More entries than the limit (10000).
    std::vector<ZipEntry> many;
    for (int i = 0; i <= 10000; ++i) many.push_back({"f" + std::to_string(i) + ".txt", ""});
    expectZipRefused("many", many, {"holds 10001 entries; the limit is 10000"});
}

}  // namespace
}  // namespace vastray::test

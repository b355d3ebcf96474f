// Volumes in uploads: a zip holding a mesh, .vdb files and vastray-volumes.json at its root
// imports the grids the manifest lists with their materials, into packages whose volumes equal
// the CLI's (`vastray import --volume ...`) and render through the service; hostile manifests and
// files are refused naming the zip, the element or file and the limit, nothing stored. The
// .vdb is the fBm cloud bench/volume_cloud writes with OpenVDB (grid 'density', over [-1, 1]^3).
#include <grpcpp/grpcpp.h>

#include <cstdlib>
#include <fstream>
#include <random>

#include "GrpcUpload.h"
#include "ZipUploadSupport.h"
#include "vastray/streamer/ScenePackage.h"
#include "vastray/v1/scene_service.grpc.pb.h"

namespace vastray::test {
namespace {

namespace fs = std::filesystem;

// One large floor triangle under the cloud (as VolumeCliTest's).
const char* kFloor =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n-3 -1.2 -3\n3 -1.2 -3\n0 -1.2 4\n3 0 2 1\n";

// The manifest of the main test, and the CLI options that say the same.
const char* kManifest = R"({"volumes": [{"file": "smoke/fog.vdb", "grid": "density", "density": 4,
  "albedo": [0.9, 0.8, 0.7], "anisotropy": 0.3, "emission_grid": "density", "emission_scale": [0.5, 0.2, 0.1],
  "codec": "fp16"}]})";
const char* kCliOptions = ":density --volume-density 4 --volume-albedo 0.9,0.8,0.7 --volume-anisotropy 0.3 "
                          "--volume-emission density --volume-emission-scale 0.5,0.2,0.1 --volume-codec fp16";

fs::path cloudDir() { return testTmpDir("server") / "volume-upload"; }

class VolumeUploadTest : public ZipUploadServerTest {
protected:
    static void SetUpTestSuite() {
        fs::create_directories(cloudDir());
        // 32^3 voxels of cloud (and Mitsuba's .vol of it, unused here).
        CommandResult cloud = runShell(std::string(VASTRAY_VOLUME_CLOUD) + " 32 " + (cloudDir() / "fog.vdb").string() +
                                       " " + (cloudDir() / "fog.vol").string());
        ASSERT_EQ(cloud.exitCode, 0) << cloud.output;
    }

    static std::string cloud() { return readBytes(cloudDir() / "fog.vdb"); }

    // Uploads floor.ply, fog.vdb and `manifest` as NAME.zip (or `entries` when given) and
    // expects it refused (expectZipRefused).
    void expectRefused(const std::string& name, const std::string& manifest, const std::vector<std::string>& phrases,
                       std::vector<ZipEntry> entries = {}) {
        if (entries.empty())
            entries = {{"floor.ply", kFloor}, {"fog.vdb", cloud()}, {"vastray-volumes.json", manifest}};
        expectZipRefused(name, entries, phrases);
    }

    std::vector<PackageVolume> packageVolumes(const fs::path& package) {
        auto reader = PackageReader::open(package.string());
        EXPECT_TRUE(reader) << reader.message();
        return reader ? (*reader)->info().volumes : std::vector<PackageVolume>{};
    }

    std::vector<Volume> volumeData(const fs::path& package) {
        auto reader = PackageReader::open(package.string());
        EXPECT_TRUE(reader) << reader.message();
        if (!reader) return {};
        auto volumes = (*reader)->readVolumes();
        EXPECT_TRUE(volumes) << volumes.message();
        return volumes ? **volumes : std::vector<Volume>{};
    }

    // A 40x30 EXR (128 spp) of `sceneId` from above the floor, looking at the cloud; the file it is in.
    fs::path render(const std::string& sceneId, int seed) {
        json request = {{"scene_id", sceneId}, {"width", 40},         {"height", 30},
                        {"spp", 128},            {"max_depth", 4},      {"seed", seed},
                        {"output_format", "exr"}, {"camera", {{"eye", {0, 1, 5}}, {"target", {0, 0, 0}}}}};
        auto job = submit(request);
        EXPECT_TRUE(job && job->status == 202) << (job ? job->body : "no response");
        if (!job || job->status != 202) return {};
        const std::string id = json::parse(job->body)["id"];
        waitForState(id, "JOB_STATE_SUCCEEDED");
        const fs::path out = dir_ / (sceneId.substr(0, 8) + "-" + std::to_string(seed) + ".exr");
        std::ofstream(out, std::ios::binary) << result(id);
        return out;
    }

    // The beauty RMSE `vastray diff` prints.
    double rmse(const fs::path& a, const fs::path& b) {
        CommandResult d = runVastray("diff " + a.string() + " " + b.string() + " --json");
        const size_t at = d.output.find("\"rmse\":");
        EXPECT_NE(at, std::string::npos) << d.output;
        return at == std::string::npos ? -1.0 : std::atof(d.output.c_str() + at + 7);
    }
};

TEST_F(VolumeUploadTest, ZipWithAVdbAndItsManifestCarriesTheVolumeLikeTheCli) {
    startServer();
    // The floor alone first: its import runs the package builder's TBB workers, which the
    // child process that reads the .vdb afterwards does not inherit.
    writeZip(dir_ / "floor.zip", {{"floor.ply", kFloor}});
    auto plain = put(dir_ / "floor.zip", "floor.zip");
    ASSERT_TRUE(plain);
    ASSERT_EQ(plain->status, 200) << plain->body;
    const std::string plainId = json::parse(plain->body)["id"];

    const fs::path zip = dir_ / "fog.zip";
    writeZip(zip, {{"floor.ply", kFloor},
                   {"smoke/fog.vdb", cloud()},
                   {"unused.vdb", cloud()},
                   {"vastray-volumes.json", kManifest}});
    auto res = put(zip, "fog.zip");
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
    const json scene = json::parse(res->body);
    EXPECT_EQ(scene["format"], "zip");
    EXPECT_EQ(scene["triangles"], "1");
    ASSERT_TRUE(scene.contains("import_warnings")) << scene.dump();
    EXPECT_NE(scene["import_warnings"].dump().find("fog.zip:unused.vdb: not imported"), std::string::npos)
        << scene.dump();
    EXPECT_TRUE(fs::is_empty(dataDir() / "tmp"));

    const fs::path served = dataDir() / "scenes" / (scene["id"].get<std::string>() + ".vast");
    const auto volumes = packageVolumes(served);
    ASSERT_EQ(volumes.size(), 1u);
    const Volume& v = volumes[0].volume;
    EXPECT_EQ(v.name, "density");
    EXPECT_EQ(v.material.albedo, (std::array<float, 3>{0.9f, 0.8f, 0.7f}));
    EXPECT_EQ(v.material.densityScale, 4.0f);
    EXPECT_EQ(v.material.anisotropy, 0.3f);
    EXPECT_EQ(v.material.emission, (std::array<float, 3>{0.5f, 0.2f, 0.1f}));
    EXPECT_TRUE(volumes[0].hasEmission);
    EXPECT_EQ(v.codec, VolumeCodec::Fp16);

    // `vastray import` of the same files with the same material: equal volumes, voxel for voxel.
    std::ofstream(dir_ / "floor.ply") << kFloor;
    std::ofstream(dir_ / "fog.vdb", std::ios::binary) << cloud();
    CommandResult cli = runVastray("import " + (dir_ / "floor.ply").string() + " -o " + (dir_ / "cli.vast").string() +
                                   " --progress none --volume " + (dir_ / "fog.vdb").string() + kCliOptions);
    ASSERT_EQ(cli.exitCode, 0) << cli.output;
    const auto cliVolumes = packageVolumes(dir_ / "cli.vast");
    ASSERT_EQ(cliVolumes.size(), 1u);
    const Volume& c = cliVolumes[0].volume;
    EXPECT_EQ(c.name, v.name);
    EXPECT_EQ(c.indexToWorld, v.indexToWorld);
    EXPECT_EQ(c.origin, v.origin);
    EXPECT_EQ(c.brickCells, v.brickCells);
    EXPECT_EQ(cliVolumes[0].brickCount, volumes[0].brickCount);
    EXPECT_EQ(c.material.albedo, v.material.albedo);
    EXPECT_EQ(c.material.densityScale, v.material.densityScale);
    EXPECT_EQ(c.material.anisotropy, v.material.anisotropy);
    EXPECT_EQ(c.material.emission, v.material.emission);
    EXPECT_EQ(c.codec, v.codec);
    const auto servedData = volumeData(served), cliData = volumeData(dir_ / "cli.vast");
    ASSERT_EQ(servedData.size(), 1u);
    ASSERT_EQ(cliData.size(), 1u);
    EXPECT_GT(servedData[0].voxels.size(), 0u);
    EXPECT_EQ(servedData[0].voxels, cliData[0].voxels);
    EXPECT_EQ(servedData[0].emissionVoxels, cliData[0].emissionVoxels);
    EXPECT_EQ(servedData[0].brickOf, cliData[0].brickOf);

    // Rendered by the service, the fog changes the image far more than another seed does (at
    // 8 spp the fog's RMSE was twice the noise's; 128 spp cut the noise 4 times).
    const fs::path fogged = render(scene["id"], 1), clear = render(plainId, 1), clearAgain = render(plainId, 2);
    ASSERT_FALSE(fogged.empty() || clear.empty() || clearAgain.empty());
    const double noise = rmse(clear, clearAgain), fog = rmse(fogged, clear);
    std::printf("clear vs clear (another seed) RMSE %.4g; with and without the fog %.4g\n", noise, fog);
    EXPECT_GE(noise, 0.0);
    EXPECT_GT(fog, 4 * noise);
}

// The manifest works the same over gRPC (one import path): the scene carries the volume.
TEST_F(VolumeUploadTest, GrpcUploadCarriesTheVolumeToo) {
    startServer();
    const fs::path zip = dir_ / "fog.zip";
    writeZip(zip, {{"floor.ply", kFloor},
                   {"fog.vdb", cloud()},
                   {"vastray-volumes.json", R"({"volumes": [{"file": "fog.vdb", "albedo": 0.5}]})"}});
    auto stub = v1::SceneService::NewStub(grpc::CreateChannel(server_.grpcAddress(), grpc::InsecureChannelCredentials()));
    v1::Scene scene;
    const grpc::Status status = uploadSceneOverGrpc(*stub, "fog.zip", readBytes(zip), 1 << 16, false, &scene);
    ASSERT_TRUE(status.ok()) << status.error_message();
    const auto volumes = packageVolumes(dataDir() / "scenes" / (scene.id() + ".vast"));
    ASSERT_EQ(volumes.size(), 1u);
    EXPECT_EQ(volumes[0].volume.name, "density") << "the file's first float grid";
    EXPECT_EQ(volumes[0].volume.material.albedo, (std::array<float, 3>{0.5f, 0.5f, 0.5f}));
    EXPECT_EQ(volumes[0].volume.material.densityScale, 1.0f) << "the CLI's default";
    EXPECT_EQ(volumes[0].volume.material.anisotropy, 0.0f) << "the CLI's default";
    EXPECT_FALSE(volumes[0].hasEmission);
}

TEST_F(VolumeUploadTest, HostileManifestsAreRefusedByElementAndLimit) {
    startServer();
    const std::string m = "vastray-volumes.json: ";
    expectRefused("notjson", "{volumes: [", {m + "is not JSON", "line 1"});
    expectRefused("array", "[1, 2]", {m + "the document is an array; expected an object"});
    expectRefused("topkey", R"({"volumes": [], "colour": 1})", {m + "the document has an unknown key 'colour'"});
    expectRefused("novolumes", "{}", {m + "the document has no \"volumes\""});
    expectRefused("volumesobject", R"({"volumes": {}})", {m + "volumes is an object; expected an array"});
    expectRefused("entrytype", R"({"volumes": ["fog.vdb"]})", {m + "volumes[0] is a string; expected an object"});
    expectRefused("nofile", R"({"volumes": [{"grid": "density"}]})", {m + "volumes[0] has no \"file\""});
    expectRefused("filetype", R"({"volumes": [{"file": 3}]})", {m + "volumes[0].file is a number; expected a string"});
    expectRefused("densitytype", R"({"volumes": [{"file": "fog.vdb", "density": "4"}]})",
                  {m + "volumes[0].density is a string; expected a number"});
    expectRefused("albedosize", R"({"volumes": [{"file": "fog.vdb", "albedo": [1, 1]}]})",
                  {m + "volumes[0].albedo is an array of 2; expected a number or an array of 3 numbers"});
    expectRefused("unknownkey", R"({"volumes": [{"file": "fog.vdb", "colour": 1}]})",
                  {m + "volumes[0] has an unknown key 'colour'"});
    expectRefused("codec", R"({"volumes": [{"file": "fog.vdb", "codec": "fp4"}]})",
                  {m + "volumes[0].codec 'fp4' is not a brick codec (expected float, fp16 or fp8)"});
    expectRefused("codectype", R"({"volumes": [{"file": "fog.vdb", "codec": 16}]})",
                  {m + "volumes[0].codec is a number; expected a string"});
    expectRefused("deep", R"({"volumes": [[[[[[[[[[1]]]]]]]]]]})", {m + "is nested more than 8 levels deep"});
    std::string many = R"({"volumes": [)";
    for (uint32_t i = 0; i <= kMaxVolumes; ++i) many += std::string(i ? "," : "") + R"({"file": "fog.vdb"})";
    expectRefused("many", many + "]}", {m + "volumes lists 65 volumes, above the limit of 64"});
    // Incompressible, so that the zip's ratio limit (a bomb) does not refuse it first.
    std::string big((1 << 20) + 1, ' ');
    std::mt19937 random(7);
    for (char& c : big) c = char('a' + random() % 26);
    expectRefused("big", big, {m + "is 1048577 bytes, above the limit of 1048576"});
}

TEST_F(VolumeUploadTest, VolumeFilesOutsideOrMissingAreRefusedByName) {
    startServer();
    const std::string m = "vastray-volumes.json: ";
    expectRefused("dotdot", R"({"volumes": [{"file": "a/../../fog.vdb"}]})",
                  {m + "volumes[0].file 'a/../../fog.vdb': leads out of the archive ('..')"});
    expectRefused("absolute", R"({"volumes": [{"file": "/etc/fog.vdb"}]})", {m + "volumes[0].file '/etc/fog.vdb': has an absolute path"});
    expectRefused("missing", R"({"volumes": [{"file": "smoke.vdb"}]})", {m + "volumes[0].file 'smoke.vdb': no such file in the zip"});
    expectRefused("notvdb", R"({"volumes": [{"file": "floor.ply"}]})", {m + "volumes[0].file 'floor.ply': expected a .vdb file"});
    // A link in the zip is refused by the extraction before the manifest is read.
    expectRefused("link", R"({"volumes": [{"file": "fog.vdb"}]})", {"entry 'fog.vdb' is a symbolic link"},
                  {{"floor.ply", kFloor}, {"fog.vdb", "/etc/passwd", true}, {"vastray-volumes.json", R"({"volumes": [{"file": "fog.vdb"}]})"}});
}

TEST_F(VolumeUploadTest, MaterialsOutOfRangeAreRefusedWithTheCliLimits) {
    startServer();
    const std::string m = "vastray-volumes.json: volumes[0].";
    expectRefused("albedo", R"({"volumes": [{"file": "fog.vdb", "albedo": 2}]})", {m + "albedo 2,2,2 is outside [0, 1]"});
    expectRefused("density", R"({"volumes": [{"file": "fog.vdb", "density": -1}]})", {m + "density -1.000000 is outside [0, 1e18]"});
    expectRefused("huge", R"({"volumes": [{"file": "fog.vdb", "density": 1e300}]})", {m + "density inf is outside [0, 1e18]"});
    expectRefused("anisotropy", R"({"volumes": [{"file": "fog.vdb", "anisotropy": 1}]})",
                  {m + "anisotropy 1.000000 is outside (-1, 1)"});
    expectRefused("emission", R"({"volumes": [{"file": "fog.vdb", "emission_grid": "density", "emission_scale": [1, 1, -2]}]})",
                  {m + "emission_scale 1,1,-2 is outside [0, 1e18]"});
    expectRefused("bothglows", R"({"volumes": [{"file": "fog.vdb", "emission_grid": "density", "temperature_grid": "density"}]})",
                  {"vastray-volumes.json: volumes[0] has both \"emission_grid\" and \"temperature_grid\""});
}

TEST_F(VolumeUploadTest, BadGridsAndCorruptFilesAreRefusedByTheFileInTheZip) {
    startServer();
    expectRefused("grid", R"({"volumes": [{"file": "fog.vdb", "grid": "smoke"}]})",
                  {"grid.zip:fog.vdb: no grid named 'smoke' (grids: density)"});
    expectRefused("emissiongrid", R"({"volumes": [{"file": "fog.vdb", "emission_grid": "heat"}]})",
                  {"emissiongrid.zip:fog.vdb: no grid named 'heat'"});
    expectRefused("temperaturegrid", R"({"volumes": [{"file": "fog.vdb", "temperature_grid": "heat"}]})",
                  {"temperaturegrid.zip:fog.vdb: no grid named 'heat'"});
    const std::string manifest = R"({"volumes": [{"file": "fog.vdb"}]})";
    const std::string bytes = cloud();
    expectRefused("truncated", manifest, {"truncated.zip:fog.vdb: "},
                  {{"floor.ply", kFloor}, {"fog.vdb", bytes.substr(0, bytes.size() / 2)}, {"vastray-volumes.json", manifest}});
    expectRefused("garbage", manifest, {"garbage.zip:fog.vdb: not a readable OpenVDB file"},
                  {{"floor.ply", kFloor}, {"fog.vdb", std::string(4096, 'x')}, {"vastray-volumes.json", manifest}});
    expectRefused("empty", manifest, {"empty.zip:fog.vdb: is empty (0 bytes)"},
                  {{"floor.ply", kFloor}, {"fog.vdb", ""}, {"vastray-volumes.json", manifest}});
}

// An asynchronous upload fails its import job with the message a synchronous one answers, and
// stores no scene.
TEST_F(VolumeUploadTest, AsyncImportJobFailsWithTheMessage) {
    startServer();
    const fs::path zip = dir_ / "bad.zip";
    writeZip(zip, {{"floor.ply", kFloor}, {"fog.vdb", cloud()},
                   {"vastray-volumes.json", R"({"volumes": [{"file": "fog.vdb", "anisotropy": -1}]})"}});
    auto res = put(zip, "bad.zip", true);
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 202) << res->body;
    const json scene = json::parse(res->body);
    const json job = waitForState(scene["import_job_id"], "JOB_STATE_FAILED");
    EXPECT_EQ(job["error"], "data: bad.zip:vastray-volumes.json: volumes[0].anisotropy -1.000000 is outside (-1, 1)");
    EXPECT_EQ(http().Get(("/v1/scenes/" + scene["id"].get<std::string>()).c_str())->status, 404);
    EXPECT_TRUE(fs::is_empty(dataDir() / "tmp"));
}

}  // namespace
}  // namespace vastray::test

// Issue 16 through the service: uploads that crashed the server, hung it or made it read a
// file outside its data folder, and a job that crashed it at every restart.
#include "ServerTestSupport.h"

namespace vastray::test {
namespace {

// Killed the server (SIGSEGV in tinygltf's JSON walk).
TEST_F(ServerTest, DeeplyNestedGltfUploadIsRefusedAndTheServerStaysUp) {
    startServer();
    const std::string deep = R"({"asset":{"version":"2.0"},"extras":)" + std::string(20000, '[') +
                             std::string(20000, ']') + "}";
    auto res = http().Put("/v1/scenes?name=deep.gltf", deep, "application/octet-stream");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400);
    EXPECT_NE(errorMessage(res).find("deep.gltf: JSON nests deeper than 64 levels"), std::string::npos)
        << res->body;
    EXPECT_EQ(http().Get("/healthz")->status, 200);
}

// One polygon of 10^6 corners kept the upload importing for minutes (no other upload ran).
TEST_F(ServerTest, HugePolygonUploadIsRefusedQuickly) {
    startServer();
    std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
    for (int i = 0; i < 1000000; ++i) obj += i % 3 == 0 ? " 1" : i % 3 == 1 ? " 2" : " 3";
    obj += "\n";
    const auto start = std::chrono::steady_clock::now();
    auto res = http().Put("/v1/scenes?name=polygon.obj", obj, "application/octet-stream");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400);
    EXPECT_NE(errorMessage(res).find("exceeds the ear-clipping limit of 16384"), std::string::npos) << res->body;
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
}

// Any client could make the server open files outside its data folder (/etc/passwd was opened).
TEST_F(ServerTest, ObjMaterialLibraryOutsideTheUploadIsRefused) {
    startServer();
    for (const std::string library : {"/etc/passwd", "../../../../etc/passwd"}) {
        const std::string obj = "mtllib " + library + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        auto res = http().Put("/v1/scenes?name=escape.obj", obj, "application/octet-stream");
        ASSERT_TRUE(res);
        EXPECT_EQ(res->status, 400) << library;
        EXPECT_NE(errorMessage(res).find("mtllib '" + library + "'"), std::string::npos) << res->body;
    }
}

// A 16384x16384 job aborted the server with std::bad_alloc. Under a 5 GiB address-space limit
// (the idle server maps 2.2 GiB) the job fails naming what it needs; the next job runs.
TEST_F(ServerTest, JobLargerThanHostMemoryFailsAndTheServerGoesOn) {
    server_.setAddressSpaceLimit(5ull << 30);
    startServer();
    const std::string sceneId = uploadSphere()["id"];
    auto res = submit({{"scene_id", sceneId}, {"width", 16384}, {"height", 16384}, {"spp", 1}});
    ASSERT_EQ(res->status, 202) << res->body;
    const json failed = waitForState(json::parse(res->body)["id"], "JOB_STATE_FAILED");
    EXPECT_NE(failed.value("error", "").find("a 16384x16384 render needs 5.0 GiB of host memory"), std::string::npos)
        << failed.dump();
    res = submit(smallJob(sceneId));
    ASSERT_EQ(res->status, 202) << res->body;
    waitForState(json::parse(res->body)["id"], "JOB_STATE_SUCCEEDED");
}

// Before the memory estimate a 16384x16384 job crashed the server, and being RUNNING at the
// next start, crashed it again at every restart. Simulated with kill -9 during each start.
TEST_F(ServerTest, JobInterruptedAtEveryStartFailsAfterThreeStarts) {
    startServer();
    const std::string sceneId = uploadSphere()["id"];
    const json body = {{"scene_id", sceneId}, {"width", 256}, {"height", 256}, {"spp", 65536}};
    auto res = submit(body);
    ASSERT_EQ(res->status, 202) << res->body;
    const std::string id = json::parse(res->body)["id"];
    for (int start = 1; start <= 3; ++start) {
        const json running = waitForState(id, "JOB_STATE_RUNNING");
        EXPECT_EQ(running["attempts"], start);
        server_.kill(SIGKILL);
        startServer();
    }
    const json job = waitForState(id, "JOB_STATE_FAILED");
    EXPECT_EQ(job["attempts"], 3);
    EXPECT_NE(job.value("error", "").find("failed 3 times (--max-attempts 3)"), std::string::npos) << job.dump();
    EXPECT_EQ(http().Get("/healthz")->status, 200);
}

// A Collada file that crashes assimp 5.2.5 (a <float_array> without its count, found by
// fuzz_import_assimp) killed the server with SIGSEGV; assimp now reads in a child process.
TEST_F(ServerTest, UploadThatCrashesAssimpIsRefusedAndTheServerStaysUp) {
    startServer();
    const std::string crashing = R"DAE(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa">0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries><library_visual_scenes><visual_scene id="s"><node><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>)DAE";
    auto res = http().Put("/v1/scenes?name=crash.dae", crashing, "application/octet-stream");
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400);
    EXPECT_NE(errorMessage(res).find("crash.dae: assimp crashed reading the file"), std::string::npos) << res->body;
    EXPECT_EQ(http().Get("/healthz")->status, 200);
}

}  // namespace
}  // namespace vastray::test

// Issue 16: inputs a hostile user would try. Each is refused by name, quickly, without a
// crash, a hang or reading a file outside the model's folder.
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <new>
#include <sstream>

#include "ImportTestFiles.h"
#include "import/ChildProcess.h"

namespace vastray::test {
namespace {

const std::string kPlyXyz = "property float x\nproperty float y\nproperty float z\n";

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string gltfWith(const std::string& extra) {
    GltfBuilder b;
    b.addPositions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    return b.json(extra + R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}])");
}

// 20,000 levels in 40 KB overflowed the stack in tinygltf's JSON walk (SIGSEGV).
TEST(HostileInput, DeeplyNestedGltfJsonIsRefusedBeforeParsing) {
    const std::string deep = "\"extras\":" + std::string(20000, '[') + std::string(20000, ']') + ",";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("deep.gltf", gltfWith(deep))), "deep.gltf: ",
                        "JSON nests deeper than 64 levels");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("deep.glb", glb("{\"a\":" + std::string(20000, '{'), ""))),
                        "deep.glb: ", "JSON nests deeper than 64 levels");
}

TEST(HostileInput, NestingInsideStringsDoesNotCount) {
    const std::string brackets = "\"extras\":{\"note\":\"" + std::string(1000, '[') + "\\\"\"},";
    auto imported = importMesh(writeFile("strings.gltf", gltfWith(brackets)));
    ASSERT_TRUE(imported.isOk()) << imported.message();
    EXPECT_EQ(imported->mesh.triangleCount(), 1u);
}

TEST(HostileInput, GltfNegativeByteStrideIsRefused) {
    std::string json = gltfWith("");
    const std::string view = "\"byteLength\":36}";
    json.replace(json.find(view), view.size(), "\"byteLength\":36,\"byteStride\":-12}");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("stride.gltf", json)), "stride.gltf: ",
                        "JSON /bufferViews/0/byteStride: expected a non-negative integer, found number -12");
}

// One polygon of 10^6 corners: as a fan its triangles all shared a corner and partitioning
// them took quadratic time (did not finish in minutes). A convex one is now clipped in O(n);
// one that cycles over a triangle is refused at once (earcut's repair of it is cubic).
TEST(HostileInput, ObjPolygonWithAMillionCornersImports) {
    std::string obj;
    const int n = 1000000;
    for (int i = 0; i < n; ++i) {
        const double angle = 6.283185307179586 * i / n;
        obj += "v " + std::to_string(std::cos(angle)) + " " + std::to_string(std::sin(angle)) + " 0\n";
    }
    obj += "f";
    for (int i = 1; i <= n; ++i) obj += " " + std::to_string(i);
    obj += "\n";
    auto imported = importMesh(writeFile("circle.obj", obj));
    ASSERT_TRUE(imported.isOk()) << imported.message();
    EXPECT_EQ(imported->report.inputTriangles, uint64_t(n - 2));
}

TEST(HostileInput, ObjPolygonCyclingAMillionTimesIsRefusedQuickly) {
    std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
    for (int i = 0; i < 1000000; ++i) obj += i % 3 == 0 ? " 1" : i % 3 == 1 ? " 2" : " 3";
    obj += "\n";
    const auto start = std::chrono::steady_clock::now();
    EXPECT_IMPORT_ERROR(importMesh(writeFile("million.obj", obj)), "million.obj: ",
                        "line 4: face: a polygon of 1000000 corners that is not convex exceeds the ear-clipping limit");
    EXPECT_LT(secondsSince(start), 5.0);  // a hang guard, not a speed target
}

TEST(HostileInput, PlyPolygonCyclingAboveTheFanLimitIsRefused) {
    std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\n" + kPlyXyz +
                      "element face 1\nproperty list int int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n5000";
    for (int i = 0; i < 5000; ++i) ply += " " + std::to_string(i % 3);
    ply += "\n";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("polygon.ply", ply)), "polygon.ply: ",
                        "face 0: a polygon of 5000 corners passes one corner more than twice");
}

TEST(HostileInput, GltfTriangleFanAboveTheCornerLimitIsRefused) {
    GltfBuilder b;
    std::vector<float> xyz;
    for (int i = 0; i < 5000; ++i) {
        const float angle = 6.2831853f * float(i) / 5000.0f;
        xyz.insert(xyz.end(), {std::cos(angle), std::sin(angle), 0.0f});
    }
    b.addPositions(xyz);
    const std::string json = b.json(R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":6}]}],"nodes":[{"mesh":0}])");
    EXPECT_IMPORT_ERROR(importMesh(writeFile("fan.gltf", json)), "fan.gltf: ",
                        "triangle fan of 5000 corners exceeds the fan limit of 4096");
}

// A FIFO with no writer blocked the import for ever; it is refused by its kind.
TEST(HostileInput, FifoIsRefusedWithoutBlocking) {
    const std::string path = tmpPath("fifo.obj");
    std::filesystem::remove(path);
    ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
    EXPECT_IMPORT_ERROR(importMesh(path), "fifo.obj: ", "is a FIFO; only regular files are read");
    std::filesystem::remove(path);
}

TEST(HostileInput, CharacterDeviceIsRefused) {
    EXPECT_IMPORT_ERROR(importObj("/dev/zero"), "zero: ", "is a character device");
}

class ObjMaterialConfinement : public ::testing::Test {
protected:
    void SetUp() override {
        folder_ = std::filesystem::path(tmpPath("confined")) / "model";
        std::filesystem::create_directories(folder_);
        outside_ = folder_.parent_path() / "outside.mtl";
        std::ofstream(outside_) << "newmtl red\nKd 1 0 0\n";
    }
    Result<ImportedMesh> importWithLibrary(const std::string& library) {
        const std::string obj = "mtllib " + library + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
        const std::filesystem::path path = folder_ / "model.obj";
        std::ofstream(path) << obj;
        return importMesh(path.string());
    }
    std::filesystem::path folder_, outside_;
};

TEST_F(ObjMaterialConfinement, ParentFolderIsRefused) {
    EXPECT_IMPORT_ERROR(importWithLibrary("../outside.mtl"), "model.obj: ",
                        "mtllib '../outside.mtl' escapes the model folder ('..')");
}

TEST_F(ObjMaterialConfinement, AbsolutePathIsRefused) {
    EXPECT_IMPORT_ERROR(importWithLibrary(outside_.string()), "model.obj: ", "is an absolute path");
    EXPECT_IMPORT_ERROR(importWithLibrary("/etc/passwd"), "model.obj: ", "mtllib '/etc/passwd' is an absolute path");
}

TEST_F(ObjMaterialConfinement, LinkOutOfTheFolderIsRefused) {
    std::filesystem::remove(folder_ / "link.mtl");
    std::filesystem::create_symlink(outside_, folder_ / "link.mtl");
    EXPECT_IMPORT_ERROR(importWithLibrary("link.mtl"), "model.obj: ",
                        "mtllib 'link.mtl' resolves outside the model folder");
}

TEST_F(ObjMaterialConfinement, LibraryInsideTheFolderIsRead) {
    std::filesystem::create_directories(folder_ / "materials");
    std::ofstream(folder_ / "materials" / "inside.mtl") << "newmtl red\nKd 1 0 0\n";
    auto imported = importWithLibrary("materials/inside.mtl");
    ASSERT_TRUE(imported.isOk()) << imported.message();
    ASSERT_EQ(imported->mesh.materials.size(), 1u);
    EXPECT_EQ(imported->mesh.materials[0].baseColor[0], 1.0f);
    EXPECT_EQ(imported->mesh.materials[0].baseColor[1], 0.0f);
}

TEST_F(ObjMaterialConfinement, MissingLibraryIsAWarning) {
    auto imported = importWithLibrary("never-written.mtl");
    ASSERT_TRUE(imported.isOk()) << imported.message();
    ASSERT_EQ(imported->report.warnings.size(), 1u);
    EXPECT_NE(imported->report.warnings[0].find("mtllib 'never-written.mtl' is not in the model's folder"),
              std::string::npos)
        << imported->report.warnings[0];
    EXPECT_EQ(imported->mesh.materials[0].baseColor[0], Material{}.baseColor[0]);
}

// glTF URIs were confined by name only; a link inside the folder led out of it.
TEST(HostileInput, GltfBufferLinkOutOfTheFolderIsRefused) {
    const std::filesystem::path folder = std::filesystem::path(tmpPath("gltf-link")) / "model";
    std::filesystem::create_directories(folder);
    const std::filesystem::path outside = folder.parent_path() / "outside.bin";
    std::ofstream(outside, std::ios::binary) << std::string(36, '\0');
    std::filesystem::remove(folder / "link.bin");
    std::filesystem::create_symlink(outside, folder / "link.bin");
    const std::string json = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":36,"uri":"link.bin"}],
        "bufferViews":[{"buffer":0,"byteLength":36}],
        "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3}],
        "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}]})";
    std::ofstream(folder / "model.gltf") << json;
    EXPECT_IMPORT_ERROR(importMesh((folder / "model.gltf").string()), "model.gltf: ",
                        "uri 'link.bin' resolves outside the model folder (a link)");
}

// Coordinates near 3e38 imported "successfully" into a package with no chunks.
TEST(HostileInput, CoordinatesBeyondTheLimitAreRefused) {
    EXPECT_IMPORT_ERROR(importMesh(writeFile("huge.obj", "v -3e38 0 0\nv 3e38 0 0\nv 0 3e38 0\nf 1 2 3\n")),
                        "huge.obj: ", "vertex 0 (-3.00000001e+38, 0, 0) lies beyond the coordinate limit of +-1e18");
    auto near = importMesh(writeFile("near.obj", "v -1e18 0 0\nv 1e18 0 0\nv 0 1e18 0\nf 1 2 3\n"));
    EXPECT_TRUE(near.isOk()) << near.message();
}

TEST(HostileInput, PlyNegativeIndexIsNamedNegative) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 4\n" + kPlyXyz +
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 -1 2\n";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("negative-index.ply", ply)), "negative-index.ply: ",
                        "face 0: index -1 is negative (vertex count 4)");
}

TEST(HostileInput, PlyHugeFloatIndexIsNamedOutOfRange) {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\n" + kPlyXyz +
                            "element face 1\nproperty list uchar float vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1e300 2\n";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("float-index.ply", ply)), "float-index.ply: ",
                        "face 0: integer value beyond +-2^53 in index list");
    std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + kPlyXyz +
                         "element face 1\nproperty list uchar double vertex_indices\nend_header\n";
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) appendRaw(binary, v);
    appendRaw(binary, uint8_t(3));
    for (double v : {0.0, -1e300, 2.0}) appendRaw(binary, v);
    EXPECT_IMPORT_ERROR(importMesh(writeFile("float-index-bin.ply", binary)), "float-index-bin.ply: ",
                        "face 0: integer value beyond +-2^53 in index list");
}

// A Collada <float_array> without its count (found by fuzz_import_assimp) makes assimp 5.2.5
// dereference a null pointer: the CLI died with SIGSEGV, and an upload of it killed the server.
// assimp now reads in a child process; its crash fails the import by the file's name.
TEST(HostileInput, AssimpCrashFailsTheImportNotTheProcess) {
    const std::string crashing = R"DAE(<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa">0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries><library_visual_scenes><visual_scene id="s"><node><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>)DAE";
    EXPECT_IMPORT_ERROR(importMesh(writeFile("crash.dae", crashing)), "crash.dae: ", "assimp crashed reading the file");
    // The same document with the count given imports: the crash is assimp's, not the format's.
    std::string fixed = crashing;
    fixed.replace(fixed.find("<float_array id=\"pa\">"), 21, "<float_array id=\"pa\" count=\"9\">");
    auto imported = importMesh(writeFile("fixed.dae", fixed));
    ASSERT_TRUE(imported.isOk()) << imported.message();
    EXPECT_EQ(imported->mesh.triangleCount(), 1u);
}

// What /proc/<pid>/stat says of a process: its state, its parent and when it started (clock
// ticks after boot: a pid used again belongs to a process that started later).
struct ReaderProcessStat {
    char state = '?';
    pid_t parent = 0;
    unsigned long long startTicks = 0;
};

// False when the process is gone (reaped).
bool readerProcessStat(pid_t pid, ReaderProcessStat& out) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string text;
    if (!std::getline(in, text)) return false;
    const size_t nameEnd = text.rfind(')');  // the command name may hold spaces and parentheses
    if (nameEnd == std::string::npos) return false;
    std::istringstream fields(text.substr(nameEnd + 1));
    fields >> out.state >> out.parent;  // fields 3 and 4
    std::string skipped;
    for (int field = 5; field < 22; ++field) fields >> skipped;
    fields >> out.startTicks;  // field 22
    return bool(fields);
}

// The processes whose parent is `parent`.
std::vector<pid_t> readerChildrenOf(pid_t parent) {
    std::vector<pid_t> children;
    for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
        const std::string name = entry.path().filename().string();
        if (name.find_first_not_of("0123456789") != std::string::npos) continue;
        ReaderProcessStat stat;
        const pid_t pid = pid_t(std::stoi(name));
        if (readerProcessStat(pid, stat) && stat.parent == parent) children.push_back(pid);
    }
    return children;
}

// Whether the process that started at `startTicks` has ended (gone, or a zombie its new parent
// has not reaped yet).
bool readerHasEnded(pid_t pid, unsigned long long startTicks) {
    ReaderProcessStat stat;
    return !readerProcessStat(pid, stat) || stat.startTicks != startTicks || stat.state == 'Z' || stat.state == 'X';
}

// The readers' child process (streamer/src/import/ChildProcess.h: assimp's, and OpenVDB's in the
// service) dies with the process that forked it. A process (standing in for `vastray import` or
// the server) runs a reader whose child never
// answers; once the child runs its reader, the process is killed with SIGKILL, which runs no
// code of its. The child must end too, within a few seconds (it is sent SIGKILL as its parent
// dies): before PR_SET_PDEATHSIG it waited for its time limit (600 s for assimp and OpenVDB),
// or for ever in a reader that hangs.
TEST(HostileInput, ReaderChildDiesWithTheProcessThatForkedIt) {
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t parent = ::fork();
    ASSERT_GE(parent, 0);
    if (parent == 0) {
        ::close(ready[0]);
        const import::ChildReader reader{"the test reader", "the test reader", 60, 0, ""};
        (void)import::runInChildProcess(
            "hang.bin", reader,
            [](int fd) {
                const char running = 1;
                import::writeToParent(fd, &running, 1);
                for (;;) ::pause();  // a reader that never finishes
            },
            [&](import::ChildAnswer& answer) {
                char running = 0;
                if (!answer.value(running)) return Status::error(answer.error());
                const ssize_t told = ::write(ready[1], &running, 1);  // the child runs its reader
                (void)told;
                answer.value(running);  // blocks until the time limit
                return Status::ok();
            });
        ::_exit(0);
    }
    ::close(ready[1]);
    pollfd p{ready[0], POLLIN, 0};
    ASSERT_EQ(::poll(&p, 1, 30000), 1) << "the reader's child did not start within 30 s";
    ::close(ready[0]);
    const std::vector<pid_t> children = readerChildrenOf(parent);
    ASSERT_EQ(children.size(), 1u);
    const pid_t child = children[0];
    ReaderProcessStat stat;
    ASSERT_TRUE(readerProcessStat(child, stat));

    ASSERT_EQ(::kill(parent, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(parent, &status, 0), parent);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!readerHasEnded(child, stat.startTicks) && std::chrono::steady_clock::now() < deadline)
        ::usleep(10000);
    const bool ended = readerHasEnded(child, stat.startTicks);
    if (!ended) ::kill(child, SIGKILL);  // not left behind by a failing test
    EXPECT_TRUE(ended) << "the reader's child (pid " << child << ") outlived its killed parent by 10 s";
}


// A reader whose child allocates past its memory limit in 64 KiB blocks (each too small for a
// mapping of its own under AddressSanitizer, whose allocator serves them from memory reserved at
// start-up, out of RLIMIT_AS's sight): the file is refused naming the limit, with RLIMIT_AS
// (std::bad_alloc in the child) or under AddressSanitizer (its heap counted; the child ends).
TEST(HostileInput, ReaderChildPastItsMemoryLimitIsRefusedNamingIt) {
    const import::ChildReader reader{"the test reader", "the test reader", 60, uint64_t(256) << 20, "256 MiB"};
    const Status status = import::runInChildProcess(
        "hog.bin", reader,
        [&](int fd) {
            std::vector<std::unique_ptr<char[]>> blocks;
            std::string answer = "allocated 1 GiB";
            try {
                for (int i = 0; i < 16384; ++i) {
                    blocks.emplace_back(new char[64 << 10]);
                    std::memset(blocks.back().get(), 1, 64 << 10);
                }
            } catch (const std::bad_alloc&) {
                blocks.clear();
                answer = import::childRanOutOfMemory() ? import::outOfMemoryText(reader, import::childMemoryLimit())
                                                       : "std::bad_alloc without the limit";
            }
            import::writeToParent(fd, answer.data(), answer.size());
        },
        [](import::ChildAnswer& answer) {
            std::vector<uint8_t> text;
            if (!answer.readToEnd(text)) return Status::error(answer.error());
            return Status::error("hog.bin: " + std::string(text.begin(), text.end()));
        });
    EXPECT_EQ(status.message(),
              "hog.bin: the test reader ran out of its 256 MiB memory limit (256 MiB) reading the file; refused");
}
}  // namespace
}  // namespace vastray::test

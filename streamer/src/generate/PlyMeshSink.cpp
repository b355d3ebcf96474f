#include "generate/PlyMeshSink.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <system_error>
#include <utility>

#include "generate/Generators.h"
#include "vastray/core/FilePath.h"

namespace vastray::gen {

// Values are copied to the file in host byte order; PLY says little endian.
static_assert(std::endian::native == std::endian::little, "PlyMeshSink writes host-order floats and ints");

PlyMeshSink::PlyMeshSink(std::string path, std::string comment)
    : path_(std::move(path)), tmpPath_(path_ + ".tmp"), comment_(std::move(comment)) {}

// Unless end() succeeded, the temporary is removed: no half-written file survives.
PlyMeshSink::~PlyMeshSink() {
    if (pendingWrite_.valid()) pendingWrite_.wait();
    discard();
}

Status PlyMeshSink::begin(uint64_t vertexCount, uint64_t faceCount) {
    file_ = std::fopen(tmpPath_.c_str(), "wb");
    if (!file_) return ioError("cannot create", errno);
    createdTmp_ = true;
    std::setvbuf(file_, nullptr, _IONBF, 0);  // we buffer ourselves, in 1 MiB blocks
    buffer_.resize(kBufferBytes);
    spare_.resize(kBufferBytes);
    expectedVertices_ = vertexCount;
    expectedFaces_ = faceCount;
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment " + comment_ + "\nelement vertex " +
                         std::to_string(vertexCount) +
                         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                         std::to_string(faceCount) +
                         "\nproperty list uchar uint vertex_indices\nend_header\n";
    assert(header.size() < buffer_.size());  // a few hundred bytes
    std::memcpy(buffer_.data() + used_, header.data(), header.size());
    used_ += header.size();
    return Status::ok();
}

Status PlyMeshSink::vertex(Vec3f position) {
    if (used_ + kVertexBytes > buffer_.size()) VASTRAY_TRY(flush());
    const float xyz[3] = {position.x, position.y, position.z};
    std::memcpy(buffer_.data() + used_, xyz, kVertexBytes);
    used_ += kVertexBytes;
    ++vertices_;
    return Status::ok();
}

Status PlyMeshSink::face(uint32_t a, uint32_t b, uint32_t c) {
    if (used_ + kFaceBytes > buffer_.size()) VASTRAY_TRY(flush());
    char* out = buffer_.data() + used_;
    const uint32_t abc[3] = {a, b, c};
    out[0] = 3;
    std::memcpy(out + 1, abc, 12);
    used_ += kFaceBytes;
    ++faces_;
    return Status::ok();
}

Status PlyMeshSink::end() {
    // A generator that miscounts would leave a PLY whose header lies: refuse to publish it.
    if (vertices_ != expectedVertices_ || faces_ != expectedFaces_) {
        return Status::error(path_ + ": generator announced " + std::to_string(expectedVertices_) +
                             " vertices and " + std::to_string(expectedFaces_) + " faces but produced " +
                             std::to_string(vertices_) + " and " + std::to_string(faces_));
    }
    VASTRAY_TRY(flush());
    VASTRAY_TRY(waitForWrite());
    std::FILE* file = file_;
    file_ = nullptr;
    if (std::fclose(file) != 0) return ioError("cannot finish writing", errno);
    if (std::rename(tmpPath_.c_str(), path_.c_str()) != 0)
        return ioError("cannot rename to final name", errno);
    createdTmp_ = false;  // it is the real file now
    return Status::ok();
}

Status PlyMeshSink::flush() {
    if (used_ == 0) return Status::ok();
    VASTRAY_TRY(waitForWrite());
    std::swap(buffer_, spare_);
    const size_t bytes = std::exchange(used_, 0);
    std::FILE* file = file_;
    const char* data = spare_.data();
    auto write = [file, data, bytes] { return std::fwrite(data, 1, bytes, file) == bytes ? 0 : errno; };
    try {
        pendingWrite_ = std::async(std::launch::async, write);
    } catch (const std::system_error&) {
        // No thread to be had: write on this one instead.
        if (int error = write()) return ioError("cannot write", error);
    }
    return Status::ok();
}

Status PlyMeshSink::waitForWrite() {
    if (!pendingWrite_.valid()) return Status::ok();
    if (int error = pendingWrite_.get()) return ioError("cannot write", error);
    return Status::ok();
}

Status PlyMeshSink::ioError(const char* what, int error) const {
    return Status::error(path_ + ": " + what + " " + tmpPath_ + ": " + std::strerror(error));
}

// Removes the temporary only if this sink created it: a failed fopen must not delete a
// stranger's file that happens to carry the same name.
void PlyMeshSink::discard() {
    if (file_) std::fclose(file_);
    file_ = nullptr;
    if (createdTmp_) std::remove(tmpPath_.c_str());
    createdTmp_ = false;
}

namespace {

bool hasPlyExtension(const std::string& path) { return lowerExtension(path) == ".ply"; }

// Passes everything to two sinks, the first one first; stops at the first error.
class TeeSink final : public MeshSink {
public:
    TeeSink(MeshSink& first, MeshSink& second) : first_(first), second_(second) {}
    Status begin(uint64_t vertices, uint64_t faces) override {
        VASTRAY_TRY(first_.begin(vertices, faces));
        return second_.begin(vertices, faces);
    }
    Status vertex(Vec3f p) override {
        VASTRAY_TRY(first_.vertex(p));
        return second_.vertex(p);
    }
    Status face(uint32_t a, uint32_t b, uint32_t c) override {
        VASTRAY_TRY(first_.face(a, b, c));
        return second_.face(a, b, c);
    }
    Status end() override {
        VASTRAY_TRY(first_.end());
        return second_.end();
    }

private:
    MeshSink& first_;
    MeshSink& second_;
};

}  // namespace
}  // namespace vastray::gen

namespace vastray {

Status generateToPly(const GenerateOptions& options, const std::string& path, MeshSink* also) {
    if (!gen::hasPlyExtension(path)) {
        return Status::error(path + ": generate writes PLY only; the output path must end in .ply");
    }
    if (Result<GeneratedCounts> counts = generatedCounts(options); !counts) return counts.status();
    std::string comment = std::string("vastray generate kind=") + generatorKindName(options.kind) +
                          " seed=" + std::to_string(options.seed) +
                          " triangles=" + std::to_string(options.triangles);
    gen::PlyMeshSink sink(path, comment);
    if (!also) return generate(options, sink);
    gen::TeeSink tee(sink, *also);
    return generate(options, tee);
}

}  // namespace vastray

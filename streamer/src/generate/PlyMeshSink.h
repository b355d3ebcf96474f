#pragma once
// MeshSink that streams a binary little-endian PLY into `path + ".tmp"` and renames it to
// `path` only after end() succeeded, so a crash or a full disk never leaves a half-written
// file under the real name. Two 1 MiB buffers: while the generator fills one, a helper
// thread writes the other, so generation and the kernel's copy overlap.
#include <cstdio>
#include <future>
#include <string>
#include <vector>

#include "vastray/streamer/Generate.h"

namespace vastray::gen {

class PlyMeshSink final : public MeshSink {
public:
    PlyMeshSink(std::string path, std::string comment);
    ~PlyMeshSink() override;
    PlyMeshSink(const PlyMeshSink&) = delete;
    PlyMeshSink& operator=(const PlyMeshSink&) = delete;

    Status begin(uint64_t vertexCount, uint64_t faceCount) override;
    Status vertex(Vec3f position) override;
    Status face(uint32_t a, uint32_t b, uint32_t c) override;
    Status end() override;

    static constexpr size_t kBufferBytes = 1 << 20;
    static constexpr size_t kVertexBytes = 12;  // 3 float
    static constexpr size_t kFaceBytes = 13;    // uchar 3 + 3 uint

private:
    Status flush();         // hands the filled buffer to the writer thread
    Status waitForWrite();  // waits for the writer thread's last block, reports its error
    Status ioError(const char* what, int error) const;
    void discard();

    std::string path_, tmpPath_, comment_;
    std::FILE* file_ = nullptr;
    std::vector<char> buffer_, spare_;  // being filled / being written
    std::future<int> pendingWrite_;     // errno of the block in flight, 0 on success
    size_t used_ = 0;
    uint64_t expectedVertices_ = 0, expectedFaces_ = 0, vertices_ = 0, faces_ = 0;
    bool createdTmp_ = false;  // tmpPath_ exists and is ours to remove
};

}  // namespace vastray::gen

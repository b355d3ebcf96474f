#pragma once
// A package's file descriptor, read with pread(): safe to share between threads that read
// different parts (chunks, volume bricks). Shared by the reader and the volume brick source it
// hands out, which may outlive it.
#include <unistd.h>

#include <cstdint>
#include <vector>

namespace vastray {

struct PackageFile {
    int fd = -1;
    PackageFile() = default;
    PackageFile(const PackageFile&) = delete;
    PackageFile& operator=(const PackageFile&) = delete;
    ~PackageFile() {
        if (fd >= 0) ::close(fd);
    }
    // False when the file ends before offset + size (it shrank since it was opened) or a read fails.
    bool read(uint64_t offset, uint64_t size, void* out) const {
        uint64_t done = 0;
        while (done < size) {
            const ssize_t n = ::pread(fd, static_cast<uint8_t*>(out) + done, size - done, off_t(offset + done));
            if (n <= 0) return false;
            done += uint64_t(n);
        }
        return true;
    }
    bool read(uint64_t offset, uint64_t size, std::vector<uint8_t>& out) const {
        out.resize(size);
        return read(offset, size, out.data());
    }
};

}  // namespace vastray

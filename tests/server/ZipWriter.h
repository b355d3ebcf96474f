#pragma once
// Zip archives written with libzip for the upload tests (ZipUploadSupport.h and its users).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zip.h>

#include <filesystem>
#include <string>
#include <vector>

namespace vastray::test {

// Entries (name, bytes) written in order; a name ending in '/' is a folder; `link` entries
// become Unix symbolic links to their bytes.
struct ZipEntry {
    std::string name, bytes;
    bool link = false;
};

inline void writeZip(const std::filesystem::path& path, const std::vector<ZipEntry>& entries) {
    int error = 0;
    zip_t* zip = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
    ASSERT_NE(zip, nullptr) << path << ": libzip error " << error;
    for (const ZipEntry& e : entries) {
        zip_int64_t index = -1;
        if (!e.name.empty() && e.name.back() == '/') {
            index = zip_dir_add(zip, e.name.c_str(), ZIP_FL_ENC_UTF_8);
        } else {
            zip_source_t* source = zip_source_buffer(zip, e.bytes.data(), e.bytes.size(), 0);
            index = zip_file_add(zip, e.name.c_str(), source, ZIP_FL_ENC_UTF_8);
        }
        ASSERT_GE(index, 0) << e.name << ": " << zip_strerror(zip);
        if (e.link) {
            ASSERT_EQ(zip_file_set_external_attributes(zip, zip_uint64_t(index), 0, ZIP_OPSYS_UNIX,
                                                       zip_uint32_t(S_IFLNK | 0777) << 16),
                      0);
        }
    }
    ASSERT_EQ(zip_close(zip), 0) << zip_strerror(zip);
}

}  // namespace vastray::test

#pragma once
// Extraction of an uploaded zip (a glTF with its .bin and images, an OBJ with its .mtl and
// maps) into a fresh folder, refusing what could escape or exhaust it: names that are
// absolute, hold "..", backslashes or control characters; symbolic links and other
// non-regular entries; encrypted entries; duplicate names; too many entries; more
// uncompressed bytes than allowed in total; an entry that expands more than maxRatio times
// (a zip bomb). Sizes are counted as the bytes come out, not taken from the archive's
// headers, which a hostile zip can forge. libzip stays in ZipArchive.cpp.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vastray/server/ServiceStatus.h"

namespace vastray::server {

struct ZipLimits {
    uint64_t maxEntries = 10000;          // files and folders
    uint64_t maxTotalBytes = 1ull << 32;  // uncompressed, all entries together
    uint64_t maxRatio = 200;              // uncompressed / compressed of one entry ...
    uint64_t ratioFloorBytes = 1u << 20;  // ... once it has produced this many bytes
    size_t maxNameLength = 1024;
    size_t maxDepth = 32;                 // folders in one entry's name
};

// Why `name` (an entry's name, "/" separated) may not be extracted, or "" when it may.
std::string unsafeZipEntryName(const std::string& name, const ZipLimits& limits);

// Extracts `zipFile` into `folder` (which must exist and be empty); `displayName` (the
// client's file name) begins every message: "models.zip: entry '../x.obj': ...". Entries
// under "__MACOSX/" (Finder's resource forks) are skipped. Returns the files extracted, as
// paths relative to `folder`. On an error, what was extracted stays for the caller to remove.
ServiceResult<std::vector<std::filesystem::path>> extractZip(const std::filesystem::path& zipFile,
                                                             const std::filesystem::path& folder,
                                                             const std::string& displayName, const ZipLimits& limits);

}  // namespace vastray::server

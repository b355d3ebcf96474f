#include "ZipArchive.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zip.h>

#include <memory>
#include <set>

namespace vastray::server {
namespace {

namespace fs = std::filesystem;

struct ZipCloser {
    void operator()(zip_t* z) const { zip_discard(z); }
};
struct ZipFileCloser {
    void operator()(zip_file_t* f) const { zip_fclose(f); }
};

ServiceStatus refuse(const std::string& displayName, const std::string& why) {
    return invalidArgument("data", displayName + ": " + why);
}

ServiceStatus refuseEntry(const std::string& displayName, const std::string& entry, const std::string& why) {
    return refuse(displayName, "entry '" + entry + "' " + why);
}

// Unix file type of an entry, from the high 16 bits of its external attributes; 0 when the
// archive was not made on Unix (no type recorded: a regular file or, by its name, a folder).
mode_t unixType(zip_t* zip, zip_uint64_t index) {
    zip_uint8_t opsys = 0;
    zip_uint32_t attributes = 0;
    if (zip_file_get_external_attributes(zip, index, 0, &opsys, &attributes) != 0) return 0;
    return opsys == ZIP_OPSYS_UNIX ? mode_t((attributes >> 16) & S_IFMT) : 0;
}

// Copies one entry into `target` (created here; never an existing file or a link), counting
// the bytes as they come out against the total and ratio limits.
ServiceStatus extractEntry(zip_t* zip, zip_uint64_t index, const zip_stat_t& stat, const fs::path& target,
                           const std::string& displayName, const ZipLimits& limits, uint64_t& totalBytes) {
    const std::string name = stat.name;
    std::unique_ptr<zip_file_t, ZipFileCloser> in(zip_fopen_index(zip, index, 0));
    if (!in) return refuseEntry(displayName, name, std::string("cannot be read: ") + zip_strerror(zip));
    const int fd = ::open(target.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) return internalError(target.string() + ": cannot create");
    std::vector<char> buffer(1 << 16);
    uint64_t entryBytes = 0;
    ServiceStatus status;
    while (status) {
        const zip_int64_t n = zip_fread(in.get(), buffer.data(), buffer.size());
        if (n < 0) {
            status = refuseEntry(displayName, name, std::string("is damaged: ") + zip_file_strerror(in.get()));
            break;
        }
        if (n == 0) break;
        entryBytes += uint64_t(n);
        totalBytes += uint64_t(n);
        if (totalBytes > limits.maxTotalBytes)
            status = refuse(displayName, "expands to more than the limit of " + std::to_string(limits.maxTotalBytes) +
                                             " bytes (at entry '" + name + "')");
        else if (entryBytes >= limits.ratioFloorBytes &&
                 entryBytes > limits.maxRatio * std::max<uint64_t>(stat.comp_size, 1))
            status = refuseEntry(displayName, name,
                                 "expands more than " + std::to_string(limits.maxRatio) + " times (" +
                                     std::to_string(stat.comp_size) + " compressed bytes; a zip bomb?)");
        else if (::write(fd, buffer.data(), size_t(n)) != n)
            status = internalError(target.string() + ": write failed");
    }
    ::close(fd);
    return status;
}

}  // namespace

std::string unsafeZipEntryName(const std::string& name, const ZipLimits& limits) {
    if (name.empty()) return "has an empty name";
    if (name.size() > limits.maxNameLength)
        return "has a name longer than " + std::to_string(limits.maxNameLength) + " characters";
    for (unsigned char c : name)
        if (c < 0x20 || c == 0x7f) return "has a control character in its name";
    if (name.find('\\') != std::string::npos) return "has a backslash in its name";
    if (name.front() == '/') return "has an absolute path";
    if (name.size() >= 2 && name[1] == ':') return "has an absolute path (a drive letter)";
    size_t depth = 0;
    for (size_t start = 0; start < name.size();) {
        size_t end = name.find('/', start);
        if (end == std::string::npos) end = name.size();
        const std::string part = name.substr(start, end - start);
        if (part == "..") return "leads out of the archive ('..')";
        if (part.empty() || part == ".") return "has an empty or '.' path segment";
        if (end < name.size() && ++depth > limits.maxDepth)
            return "is nested more than " + std::to_string(limits.maxDepth) + " folders deep";
        start = end + 1;
    }
    return "";
}

ServiceResult<std::vector<fs::path>> extractZip(const fs::path& zipFile, const fs::path& folder,
                                                const std::string& displayName, const ZipLimits& limits) {
    int error = 0;
    std::unique_ptr<zip_t, ZipCloser> zip(zip_open(zipFile.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &error));
    if (!zip) {
        zip_error_t z;
        zip_error_init_with_code(&z, error);
        const std::string why = zip_error_strerror(&z);
        zip_error_fini(&z);
        return refuse(displayName, "not a readable zip archive: " + why);
    }
    const zip_int64_t entries = zip_get_num_entries(zip.get(), 0);
    if (entries < 0 || uint64_t(entries) > limits.maxEntries)
        return refuse(displayName, "holds " + std::to_string(entries) + " entries; the limit is " +
                                       std::to_string(limits.maxEntries));
    std::vector<fs::path> files;
    std::set<std::string> seen;
    uint64_t totalBytes = 0;
    for (zip_uint64_t i = 0; i < zip_uint64_t(entries); ++i) {
        zip_stat_t stat;
        if (zip_stat_index(zip.get(), i, ZIP_FL_ENC_RAW, &stat) != 0 || !(stat.valid & ZIP_STAT_NAME))
            return refuse(displayName, "entry " + std::to_string(i) + " cannot be read");
        std::string name = stat.name;
        if (const std::string why = unsafeZipEntryName(name, limits); !why.empty())
            return refuseEntry(displayName, name, why);
        if (name.rfind("__MACOSX/", 0) == 0) continue;
        const bool isFolder = name.back() == '/';
        const mode_t type = unixType(zip.get(), i);
        if (type == S_IFLNK) return refuseEntry(displayName, name, "is a symbolic link");
        if (type != 0 && type != S_IFREG && type != S_IFDIR) return refuseEntry(displayName, name, "is not a regular file");
        if ((stat.valid & ZIP_STAT_ENCRYPTION_METHOD) && stat.encryption_method != ZIP_EM_NONE)
            return refuseEntry(displayName, name, "is encrypted");
        if (isFolder) name.pop_back();
        if (!seen.insert(name).second) return refuseEntry(displayName, name, "appears twice");
        const fs::path target = folder / name;
        std::error_code made;
        fs::create_directories(isFolder ? target : target.parent_path(), made);
        if (made) return refuseEntry(displayName, name, "conflicts with an earlier entry (a file where a folder is)");
        if (isFolder || type == S_IFDIR) continue;
        if (ServiceStatus s = extractEntry(zip.get(), i, stat, target, displayName, limits, totalBytes); !s) return s;
        files.push_back(fs::path(name));
    }
    return files;
}

}  // namespace vastray::server

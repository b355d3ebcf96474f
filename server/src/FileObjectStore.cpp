// ObjectStore on the local file system: objects are files under the data folder, put by
// rename(2) from the scratch folder (atomic within one file system).
#include <fcntl.h>
#include <unistd.h>

#include "vastray/server/Storage.h"

namespace vastray::server {
namespace {

namespace fs = std::filesystem;

// Flushes a file or folder to disk so that a rename survives a power loss, not just a crash.
void syncPath(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

bool validKey(const std::string& key) {
    if (key.empty() || key.front() == '/' || key.find("..") != std::string::npos) return false;
    return key.rfind("tmp/", 0) != 0;
}

class FileObjectStore final : public ObjectStore {
public:
    FileObjectStore(fs::path root, fs::path scratch) : root_(std::move(root)), scratch_(std::move(scratch)) {}

    fs::path scratchDir() const override { return scratch_; }

    Status put(const std::string& key, const fs::path& file) override {
        if (!validKey(key)) return Status::error("object key '" + key + "' is not valid");
        const fs::path target = root_ / key;
        std::error_code error;
        fs::create_directories(target.parent_path(), error);
        if (error) return Status::error(target.parent_path().string() + ": " + error.message());
        syncPath(file);
        fs::rename(file, target, error);
        if (error)
            return Status::error("cannot move " + file.string() + " to " + target.string() + ": " +
                                 error.message());
        syncPath(target.parent_path());
        return Status::ok();
    }

    Result<fs::path> localPath(const std::string& key) const override {
        if (!validKey(key)) return Status::error("object key '" + key + "' is not valid");
        fs::path path = root_ / key;
        std::error_code error;
        if (!fs::is_regular_file(path, error)) return Status::error(path.string() + ": no such object");
        return path;
    }

    Status remove(const std::string& key) override {
        if (!validKey(key)) return Status::error("object key '" + key + "' is not valid");
        std::error_code error;
        fs::remove(root_ / key, error);
        if (error) return Status::error((root_ / key).string() + ": " + error.message());
        return Status::ok();
    }

    uint64_t availableBytes() const override {
        std::error_code error;
        const fs::space_info space = fs::space(root_, error);
        return error ? 0 : space.available;
    }

private:
    fs::path root_, scratch_;
};

}  // namespace

Result<std::unique_ptr<ObjectStore>> openFileObjectStore(const fs::path& dataDir) {
    std::error_code error;
    fs::remove_all(dataDir / "tmp", error);
    for (const char* folder : {"tmp", "scenes", "results"}) {
        fs::create_directories(dataDir / folder, error);
        if (error) return Status::error((dataDir / folder).string() + ": " + error.message());
    }
    return std::unique_ptr<ObjectStore>(std::make_unique<FileObjectStore>(dataDir, dataDir / "tmp"));
}

Result<std::unique_ptr<ObjectStore>> openSharedFileObjectStore(const fs::path& dir,
                                                               const std::string& replica) {
    std::error_code error;
    const fs::path scratch = dir / "tmp" / replica;
    for (const fs::path& folder : {scratch, dir / "scenes", dir / "results", dir / "tiles"}) {
        fs::create_directories(folder, error);
        if (error) return Status::error(folder.string() + ": " + error.message());
    }
    return std::unique_ptr<ObjectStore>(std::make_unique<FileObjectStore>(dir, scratch));
}

}  // namespace vastray::server

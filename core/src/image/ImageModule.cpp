// writeImageFile (but for .pfm, PfmFile.h), diffImageFiles, readImageChannels, writeRgba8Png, readStoredImage,
// writeStoredImage, readRgba8Image and decodeRgba8Image (but for .ktx2, Ktx2Image.h) forward to the
// OpenImageIO module, loaded once on first use.
#include "ImageModule.h"
#include "Ktx2Image.h"
#include "PfmFile.h"

#include <dlfcn.h>

#include <cctype>

#include <filesystem>
#include <vector>

#include "vastray/core/FilePath.h"
#include "vastray/core/ImageDiff.h"
#include "vastray/core/ImageFile.h"

namespace vastray {
namespace {

// Where the module is looked for: $VASTRAY_IMAGE_MODULE alone when set; else beside the
// running program, then where this build wrote it (tests and benchmarks live in sub-folders).
std::vector<std::string> moduleCandidates() {
    if (const char* path = std::getenv("VASTRAY_IMAGE_MODULE"); path && *path) return {path};
    std::vector<std::string> candidates;
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (!error) candidates.push_back((self.parent_path() / VASTRAY_IMAGE_MODULE_FILE).string());
    if (candidates.empty() || candidates.front() != VASTRAY_IMAGE_MODULE_BUILD_PATH)
        candidates.push_back(VASTRAY_IMAGE_MODULE_BUILD_PATH);
    return candidates;
}

struct LoadedModule {
    const ImageModuleApi* api = nullptr;
    Status status;
};

LoadedModule load() {
    std::string tried;
    for (const std::string& path : moduleCandidates()) {
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = dlerror();  // names the path
            tried += "\n  " + (why ? std::string(why) : path + ": cannot be loaded");
            continue;
        }
        using Entry = const ImageModuleApi* (*)();
        const auto entry = reinterpret_cast<Entry>(dlsym(handle, VASTRAY_IMAGE_MODULE_SYMBOL));
        const ImageModuleApi* api = entry ? entry() : nullptr;
        if (api && api->version == kImageModuleVersion) return {api, Status::ok()};
        tried += "\n  " + path + ": " +
                 (api ? "built for another version of vastray" : "not a vastray image module");
        dlclose(handle);
    }
    return {nullptr, Status::error(std::string("the image module " VASTRAY_IMAGE_MODULE_FILE
                                               " (OpenImageIO) could not be loaded; tried:") +
                                   tried + "\n(set VASTRAY_IMAGE_MODULE to its path, or rebuild vastray)")};
}

const LoadedModule& module() {
    static const LoadedModule loaded = load();
    return loaded;
}

}  // namespace

Status loadImageModule() { return module().status; }

Status writeImageFile(const std::string& path, const RenderImage& image) {
    if (lowerExtension(path) == ".pfm") return writePfmFile(path, image);
    const LoadedModule& m = module();
    if (!m.api) return m.status.withContext(path + ": cannot write: ");
    return m.api->writeImageFile(path, image);
}

Result<ImageDiffReport> diffImageFiles(const std::string& pathA, const std::string& pathB) {
    const LoadedModule& m = module();
    if (!m.api) return m.status.withContext("cannot read images: ");
    return m.api->diffImageFiles(pathA, pathB);
}

Result<ImageChannels> readImageChannels(const std::string& path, const std::vector<std::string>& names,
                                        uint64_t maxPixels) {
    const LoadedModule& m = module();
    if (!m.api) return m.status.withContext(path + ": cannot read: ");
    return m.api->readImageChannels(path, names, maxPixels);
}

Status writeRgba8Png(const std::string& path, uint32_t width, uint32_t height,
                     const std::vector<uint8_t>& rgba) {
    const LoadedModule& m = module();
    if (!m.api) return m.status.withContext(path + ": cannot write: ");
    return m.api->writeRgba8Png(path, width, height, rgba);
}

Result<StoredImage> readStoredImage(const std::string& path) {
    const LoadedModule& m = module();
    if (!m.api) return m.status.withContext(path + ": cannot read: ");
    return m.api->readStoredImage(path);
}

Status writeStoredImage(const std::string& path, const StoredImage& image) {
    const LoadedModule& m = module();
    if (!m.api) return m.status.withContext(path + ": cannot write: ");
    return m.api->writeStoredImage(path, image);
}

Result<Rgba8Image> readRgba8Image(const std::string& path, uint64_t maxPixels) {
    if (lowerExtension(path) == ".ktx2") return readKtx2Image(path, maxPixels);
    const LoadedModule& m = module();
    if (!m.api) return m.status.withContext(path + ": cannot read: ");
    return m.api->readRgba8Image(path, maxPixels);
}

Result<Rgba8Image> decodeRgba8Image(const std::string& name, const std::string& extension,
                                    const std::vector<uint8_t>& bytes, uint64_t maxPixels) {
    if (extension == ".ktx2") return decodeKtx2Image(name, bytes, maxPixels);
    const LoadedModule& m = module();
    if (!m.api) return m.status.withContext(name + ": cannot read: ");
    return m.api->decodeRgba8Image(name, extension, bytes, maxPixels);
}

}  // namespace vastray

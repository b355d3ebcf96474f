#pragma once
// The volumes of a zip upload: `vastray-volumes.json` at the zip's root lists the .vdb grids to
// import with their materials, the same fields and limits as `vastray import --volume ...`
// (docs/SERVICE.md, "Volumes in a zip"). It travels inside the upload, so the scene id (the
// SHA-256 of the uploaded bytes) still determines the scene. nlohmann stays in VolumeManifest.cpp.
#include <filesystem>
#include <string>
#include <vector>

#include "vastray/server/ServiceStatus.h"
#include "vastray/streamer/VolumeImport.h"

namespace vastray::server {

inline constexpr const char* kVolumeManifestName = "vastray-volumes.json";
// A manifest is a few lines per volume: larger files are refused before they are parsed.
constexpr uint64_t kMaxVolumeManifestBytes = 1 << 20;

struct ZipVolumes {
    std::vector<VolumeSource> sources;  // paths inside the extraction folder; labels "ZIP:ENTRY"
    std::vector<std::string> warnings;  // .vdb files the manifest does not list (not imported)
};

// The manifest of the zip `zipName` extracted into `folder` (`files`: its files, relative to
// `folder`), or no sources when it has none. Refusals name the zip, the manifest, the element
// and the limit: "cars.zip:vastray-volumes.json: volumes[0].file 'a/../x.vdb': leads out of
// the archive ('..')". Material ranges are readVolumes' to check.
ServiceResult<ZipVolumes> readVolumeManifest(const std::filesystem::path& folder,
                                             const std::vector<std::filesystem::path>& files,
                                             const std::string& zipName);

}  // namespace vastray::server

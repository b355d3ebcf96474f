#pragma once
// A version 6 package's volume bricks, read one at a time (docs/PACKAGE_FORMAT.md, "Volumes"):
// the cell table and brick index are read and checked when the volumes are opened, each brick
// when someone asks for it.
#include <memory>
#include <string>
#include <vector>

#include "package/PackageFile.h"
#include "vastray/core/Result.h"
#include "vastray/core/Volume.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

// What readBrick needs of one volume: where its bricks start and each brick's checksum and
// largest density as its index records them.
struct StoredVolumeBricks {
    std::string name;          // "scene.vast: volume 0 'density': "
    uint64_t firstBrick = 0;   // file offset of brick 0
    bool emission = false;
    uint32_t version = 0;              // the package's format: from 14, bricks are leaves of `codec`
    VolumeCodec codec = VolumeCodec::Float;
    std::vector<uint64_t> checksum;
    std::vector<float> maximum;
};

class PackageVolumeBricks final : public VolumeBrickSource {
public:
    PackageVolumeBricks(std::shared_ptr<const PackageFile> file, std::vector<StoredVolumeBricks> volumes, bool leaves)
        : file_(std::move(file)), volumes_(std::move(volumes)), leaves_(leaves) {}
    // Version 14 leaves are decoded (NanoVDB's C++ access) into the values and given verbatim.
    Status readBrick(uint32_t volume, uint32_t brick, float* density, float* emission, uint8_t* leaves) const override;
    std::optional<VolumeCodec> leafCodec(uint32_t volume) const override {
        if (!leaves_ || volume >= volumes_.size()) return std::nullopt;
        return volumes_[volume].codec;
    }

private:
    std::shared_ptr<const PackageFile> file_;
    std::vector<StoredVolumeBricks> volumes_;
    bool leaves_;
};

// Reads version 6 (or later: `version`) volume `p`'s cell table and brick index (checksum, every brick number in range,
// every recorded maximum finite in [0, 1e18], reserved words 0) into `volume` (brickOf, majorants
// from the recorded maxima) and `bricks`. `name` starts every message.
Status readVolumeTable(const PackageFile& file, uint32_t version, const PackageVolume& p, const std::string& name,
                       Volume& volume, StoredVolumeBricks& bricks);

}  // namespace vastray

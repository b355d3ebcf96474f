// OpenVDB float grids into vastray volumes (VolumeImport.h). The only translation unit of the
// product that includes OpenVDB: its headers take ~25 s to compile.
#include <openvdb/io/Archive.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/io/io.h>
#include <openvdb/openvdb.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <charconv>
#include <cmath>
#include <fstream>
#include <ios>
#include <mutex>
#include <new>
#include <vector>

#include "import/ImportCommon.h"
#include "vastray/core/Blackbody.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/Utf8.h"
#include "vastray/streamer/Import.h"
#include "vastray/streamer/VolumeImport.h"

namespace vastray {
namespace {

using import::errorIn;
using openvdb::Coord;
using openvdb::CoordBBox;
using openvdb::FloatGrid;
using openvdb::io::GridDescriptor;

constexpr size_t kMaxListedGrids = 16;          // grid names quoted in one message
constexpr size_t kMaxQuotedNameBytes = 200;     // a grid name in a message is cut to this
constexpr uint32_t kMarkedCell = kNoBrick - 1;  // holds a nonzero value; its brick not numbered yet

void initializeOpenVdb() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

// The shortest text that reads back as x ("1e+18", "0.5", "nan").
template <typename T>
std::string numberText(T x) {
    char text[64];
    return std::string(text, std::to_chars(text, text + sizeof(text), x).ptr);
}

std::string coordText(const Coord& c) {
    return "(" + std::to_string(c.x()) + ", " + std::to_string(c.y()) + ", " + std::to_string(c.z()) + ")";
}

std::string quoted(const std::string& name) {
    return "'" + cutUtf8(validUtf8(name), kMaxQuotedNameBytes) + "'";
}

// The file's size, refused when it is not a regular file, is empty or is above the limit.
Result<uint64_t> checkedFileSize(const std::string& path, const std::string& fileName) {
    auto fd = import::openRegularFile(path);  // refuses FIFOs, devices and folders by kind
    if (!fd) return fd.status();
    struct stat st {};
    const int rc = ::fstat(*fd, &st);
    ::close(*fd);
    if (rc != 0) return errorIn(fileName, "cannot determine the file size");
    const uint64_t size = uint64_t(st.st_size);
    if (size == 0) return errorIn(fileName, "is empty (0 bytes); not an OpenVDB file");
    if (size > kMaxVdbFileBytes)
        return errorIn(fileName, "is " + std::to_string(size) + " bytes, above the limit of " +
                                     std::to_string(kMaxVdbFileBytes) + " (" + formatBytes(kMaxVdbFileBytes) +
                                     ") for .vdb files");
    return size;
}

// One grid of the file: its descriptor, and the grid itself when the file has no grid offsets
// (written to a stream, so every grid is read as it comes).
struct VdbEntry {
    GridDescriptor descriptor;
    openvdb::GridBase::Ptr grid;
    std::string name() const { return GridDescriptor::nameAsString(descriptor.uniqueName()); }
    bool isFloat() const { return descriptor.gridType() == FloatGrid::gridType(); }
};

// The file, read through a stream of our own rather than openvdb::io::File: File reads a
// truncated uncompressed file without a word (the voxels past the cut come back as whatever
// the buffers held; a cut in the topology leaves the grid empty). Here every short read throws
// (std::ios_base::failure) and each grid's byte range must lie inside the file. Throws what
// OpenVDB throws; the caller turns it into an error.
class VdbArchive : public openvdb::io::Archive {
public:
    VdbArchive(const std::string& path, uint64_t fileSize)
        : in_(path, std::ios::binary), fileSize_(fileSize) {
        in_.exceptions(std::ios::failbit | std::ios::badbit);
    }

    // The header, the file's metadata and every grid's descriptor.
    Status scan(const std::string& fileName, std::vector<VdbEntry>& entries) {
        readHeader(in_);
        streamMetadata_ = std::make_shared<openvdb::io::StreamMetadata>();
        streamMetadata_->setSeekable(true);
        openvdb::io::setStreamMetadataPtr(in_, streamMetadata_, /*transfer=*/false);
        setFormatVersion(in_);
        setLibraryVersion(in_);
        setDataCompression(in_);
        openvdb::MetaMap fileMetadata;
        fileMetadata.readMeta(in_);
        const int32_t count = readGridCount(in_);
        for (int32_t i = 0; i < count; ++i) {
            VdbEntry entry;
            entry.descriptor.read(in_);  // throws for a grid type OpenVDB does not know
            if (inputHasGridOffsets()) {
                // Each grid starts after its descriptor: the scan moves forward, at most once per byte.
                const int64_t here = int64_t(in_.tellg());
                const GridDescriptor& d = entry.descriptor;
                if (!(here <= d.getGridPos() && d.getGridPos() <= d.getEndPos() &&
                      uint64_t(d.getEndPos()) <= fileSize_))
                    return errorIn(fileName, "grid " + quoted(entry.name()) + " claims bytes " +
                                                 std::to_string(d.getGridPos()) + " to " +
                                                 std::to_string(d.getEndPos()) + " of a " +
                                                 std::to_string(fileSize_) + "-byte file (truncated?)");
                d.seekToEnd(in_);
            } else {
                entry.grid = readGridHere(entry.descriptor);
            }
            entries.push_back(std::move(entry));
        }
        return Status::ok();
    }

    // The grid of `entry` with its tree (an instance shares its parent's tree).
    Result<openvdb::GridBase::Ptr> read(const std::string& fileName, const std::vector<VdbEntry>& entries,
                                        const VdbEntry& entry) {
        openvdb::GridBase::Ptr grid = gridOf(entry);
        if (!entry.descriptor.isInstance()) return grid;
        const auto parent = std::find_if(entries.begin(), entries.end(), [&](const VdbEntry& e) {
            return e.descriptor.uniqueName() == entry.descriptor.instanceParentName();
        });
        if (parent == entries.end() || parent->descriptor.isInstance())
            return errorIn(fileName,
                           "grid " + quoted(entry.name()) + " is an instance of " +
                               quoted(GridDescriptor::nameAsString(entry.descriptor.instanceParentName())) +
                               ", which the file does not hold as a grid of its own");
        grid->setTree(gridOf(*parent)->baseTreePtr());  // throws when the trees' types differ
        return grid;
    }

private:
    openvdb::GridBase::Ptr gridOf(const VdbEntry& entry) {
        if (entry.grid) return entry.grid;
        entry.descriptor.seekToGrid(in_);
        return readGridHere(entry.descriptor);
    }
    openvdb::GridBase::Ptr readGridHere(const GridDescriptor& d) {
        openvdb::GridBase::Ptr grid = openvdb::GridBase::createGrid(d.gridType());
        grid->setSaveFloatAsHalf(d.saveFloatAsHalf());
        Archive::readGrid(grid, d, in_);
        return grid;
    }

    std::ifstream in_;
    uint64_t fileSize_;
    // OpenVDB keeps a pointer to this pointer in the stream: it lives as long as the stream.
    openvdb::io::StreamMetadata::Ptr streamMetadata_;
};

// "density, vel (vec3s), ..." for messages.
std::string gridList(const std::vector<VdbEntry>& entries) {
    std::string list;
    for (size_t i = 0; i < entries.size() && i < kMaxListedGrids; ++i) {
        if (i > 0) list += ", ";
        list += cutUtf8(validUtf8(entries[i].name()), kMaxQuotedNameBytes);
        if (!entries[i].isFloat())
            list += " (" + openvdb::GridBase::createGrid(entries[i].descriptor.gridType())->valueType() + ")";
    }
    if (entries.size() > kMaxListedGrids) list += ", ... (" + std::to_string(entries.size()) + " grids)";
    return list;
}

// The grid named `gridName` (by its unique name first, as openvdb::io::File finds it), or the
// first float grid when the name is empty.
Result<const VdbEntry*> selectGrid(const std::string& fileName, const std::vector<VdbEntry>& entries,
                                   const std::string& gridName) {
    if (entries.empty()) return errorIn(fileName, "holds no grids");
    if (gridName.empty()) {
        for (const VdbEntry& e : entries)
            if (e.isFloat()) return &e;
        return errorIn(fileName,
                       "no float grid (grids: " + gridList(entries) + "); vastray reads float grids");
    }
    auto found =
        std::find_if(entries.begin(), entries.end(), [&](const VdbEntry& e) { return e.name() == gridName; });
    if (found == entries.end())
        found = std::find_if(entries.begin(), entries.end(),
                             [&](const VdbEntry& e) { return e.descriptor.gridName() == gridName; });
    if (found == entries.end())
        return errorIn(fileName, "no grid named " + quoted(gridName) + " (grids: " + gridList(entries) + ")");
    if (!found->isFloat()) {
        const std::string type = openvdb::GridBase::createGrid(found->descriptor.gridType())->valueType();
        return errorIn(fileName, "grid " + quoted(found->name()) + " is of type " + type +
                                     "; vastray reads float grids");
    }
    return &*found;
}

bool isDensity(float x) { return x >= 0.0f && x <= kMaxVolumeDensity; }  // false for NaN

Status densityError(const std::string& where, const std::string& what, float x) {
    return Status::error(where + what + " has density " + numberText(x) +
                         "; densities are finite and in [0, " + numberText(kMaxVolumeDensity) + "]");
}

// The brick grid over the active values' index box [lo, hi]: trilinear interpolation makes the
// points of (lo - 1, hi + 1) nonzero, so the cells cover [lo - 1, hi + 1]. 64-bit arithmetic;
// the limits are checked before anything is allocated.
Status setBrickGrid(const std::string& where, const CoordBBox& box, Volume& volume) {
    const int64_t size = kVolumeBrickSize;
    uint64_t cells[3];
    for (int a = 0; a < 3; ++a) {
        const int64_t lo = int64_t(box.min()[a]) - 1, hi = int64_t(box.max()[a]) + 1;
        if (lo < -kMaxVdbIndex || hi > kMaxVdbIndex)
            return Status::error(where + "active values span the index box " + coordText(box.min()) + " to " +
                                 coordText(box.max()) + ", beyond the limit of +-" +
                                 std::to_string(kMaxVdbIndex) +
                                 " (float index space keeps whole voxels only that far)");
        const int64_t origin =
            (lo >= 0 ? lo / size : -((-lo + size - 1) / size)) * size;  // floor to a multiple of 8
        volume.origin[a] = int32_t(origin);
        cells[a] = uint64_t((hi - origin) / size + 1);
    }
    // At most 2^22 + 2 cells per axis: the product of two fits in 64 bits, and of three when
    // the first two are within the limit.
    const uint64_t xy = cells[0] * cells[1];
    if (xy > kMaxVolumeBrickCells || xy * cells[2] > kMaxVolumeBrickCells)
        return Status::error(where + "the brick grid over the active values (index box " +
                             coordText(box.min()) + " to " + coordText(box.max()) + ") has " +
                             std::to_string(cells[0]) + " x " + std::to_string(cells[1]) + " x " +
                             std::to_string(cells[2]) + " cells, more than the limit of " +
                             std::to_string(kMaxVolumeBrickCells));
    for (int a = 0; a < 3; ++a) volume.brickCells[a] = uint32_t(cells[a]);
    return Status::ok();
}

// The brick cell holding index-space voxel c (inside the brick grid).
uint64_t cellOf(const Volume& v, const Coord& c) {
    uint64_t cell[3];
    for (int a = 0; a < 3; ++a) {
        const int64_t offset = int64_t(c[a]) - v.origin[a];
        assert(offset >= 0 && offset < int64_t(kVolumeBrickSize) * v.brickCells[a]);
        cell[a] = uint64_t(offset) / kVolumeBrickSize;
    }
    return cell[0] + v.brickCells[0] * (cell[1] + uint64_t(v.brickCells[1]) * cell[2]);
}

// Calls visit(cell) for every brick cell of an active tile's box (tiles are 128 or more voxels
// a side, aligned to their size, so they cover whole cells).
template <typename Visit>
void forTileCells(const Volume& v, const CoordBBox& tile, Visit&& visit) {
    const uint64_t lo = cellOf(v, tile.min()), hi = cellOf(v, tile.max());
    const uint64_t nx = v.brickCells[0], nxy = nx * v.brickCells[1];
    for (uint64_t z = lo / nxy; z <= hi / nxy; ++z)
        for (uint64_t y = lo % nxy / nx; y <= hi % nxy / nx; ++y)
            for (uint64_t x = lo % nx; x <= hi % nx; ++x) visit(x + nx * y + nxy * z);
}

// The active tiles above the leaves (the leaves' voxels are read leaf by leaf).
FloatGrid::TreeType::ValueOnCIter activeTiles(const FloatGrid& grid) {
    FloatGrid::TreeType::ValueOnCIter it = grid.tree().cbeginValueOn();
    it.setMaxDepth(FloatGrid::TreeType::ValueOnCIter::LEAF_DEPTH - 1);
    return it;
}

// Checks every active value and marks the cells holding a nonzero one (kMarkedCell); returns
// how many. Each leaf (8^3 voxels, 8-aligned) lies in one cell.
Result<uint64_t> markCells(const std::string& where, const FloatGrid& grid, Volume& volume) {
    volume.brickOf.assign(volume.cellCount(), kNoBrick);
    uint64_t marked = 0;
    auto mark = [&](uint64_t cell) {
        marked += volume.brickOf[cell] != kMarkedCell;
        volume.brickOf[cell] = kMarkedCell;
    };
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        bool nonzero = false;
        for (auto voxel = leaf->cbeginValueOn(); voxel; ++voxel) {
            if (!isDensity(*voxel))
                return densityError(where, "voxel " + coordText(voxel.getCoord()), *voxel);
            nonzero |= *voxel != 0.0f;
        }
        if (nonzero) mark(cellOf(volume, leaf->origin()));
    }
    for (auto tile = activeTiles(grid); tile; ++tile) {
        if (!tile.isTileValue()) continue;
        CoordBBox box;
        tile.getBoundingBox(box);
        if (!isDensity(*tile))
            return densityError(where, "tile " + coordText(box.min()) + " to " + coordText(box.max()), *tile);
        if (*tile != 0.0f) forTileCells(volume, box, mark);
    }
    return marked;
}

// Numbers the marked cells' bricks in cell order and copies the active values into them.
void fillBricks(const FloatGrid& grid, uint64_t brickCount, Volume& volume) {
    uint32_t next = 0;
    for (uint32_t& brick : volume.brickOf)
        if (brick == kMarkedCell) brick = next++;
    volume.voxels.assign(brickCount * kVolumeBrickVoxels, 0.0f);
    const int32_t size = int32_t(kVolumeBrickSize);
    for (auto leaf = grid.tree().cbeginLeaf(); leaf; ++leaf) {
        const uint32_t brick = volume.brickOf[cellOf(volume, leaf->origin())];
        if (brick == kNoBrick) continue;
        float* voxels = &volume.voxels[uint64_t(brick) * kVolumeBrickVoxels];
        for (auto voxel = leaf->cbeginValueOn(); voxel; ++voxel) {
            const Coord local = voxel.getCoord() - leaf->origin();
            voxels[local.x() + size * (local.y() + size * local.z())] = *voxel;
        }
    }
    for (auto tile = activeTiles(grid); tile; ++tile) {
        if (!tile.isTileValue() || *tile == 0.0f) continue;
        CoordBBox box;
        tile.getBoundingBox(box);
        const float value = *tile;
        forTileCells(volume, box, [&](uint64_t cell) {
            float* voxels = &volume.voxels[uint64_t(volume.brickOf[cell]) * kVolumeBrickVoxels];
            std::fill(voxels, voxels + kVolumeBrickVoxels, value);
        });
    }
}

// indexToWorld from the grid's transform, which must be linear. OpenVDB multiplies row
// vectors, world = (i, j, k, 1) * M: column c of M's first three rows is row c of our linear
// part, and M's last row is the translation.
Status setTransform(const std::string& where, const openvdb::math::Transform& transform, Volume& volume) {
    if (!transform.isLinear())
        return Status::error(where + "its transform is a " + transform.mapType() +
                             ", not linear; vastray reads linear (affine) transforms");
    const openvdb::math::Mat4d m = transform.baseMap()->getAffineMap()->getMat4();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            const double x = c < 3 ? m(c, r) : m(3, r);
            if (!(std::fabs(x) <= double(kMaxAbsCoordinate)))
                return Status::error(where + "its transform has the entry " + numberText(x) +
                                     ", not finite or beyond +-" + numberText(kMaxAbsCoordinate));
            volume.indexToWorld[4 * r + c] = float(x);
        }
    if (!finishVolumeTransform(volume)) return Status::error(where + "its transform is not invertible");
    const Aabb& b = volume.worldBounds;
    const float limit = kMaxAbsCoordinate;
    if (!(b.lo.x >= -limit && b.lo.y >= -limit && b.lo.z >= -limit && b.hi.x <= limit && b.hi.y <= limit &&
          b.hi.z <= limit))
        return Status::error(where + "its world bounds reach beyond the coordinate limit of +-" +
                             numberText(limit));
    return Status::ok();
}

Result<Volume> volumeOf(const std::string& where, const FloatGrid& grid, const VolumeMaterial& material) {
    if (!(grid.background() == 0.0f))
        return Status::error(where + "background " + numberText(grid.background()) +
                             " is not 0; vastray reads fog volumes (a level set has a nonzero background)");
    CoordBBox box;
    if (!grid.tree().evalActiveVoxelBoundingBox(box))
        return Status::error(where + "has no active values (an empty grid)");
    Volume volume;
    VASTRAY_TRY(setBrickGrid(where, box, volume));
    auto bricks = markCells(where, grid, volume);
    if (!bricks) return bricks.status();
    if (*bricks > kMaxVolumeBricks)
        return Status::error(where + std::to_string(*bricks) +
                             " brick cells hold nonzero values, more than the limit of " +
                             std::to_string(kMaxVolumeBricks) + " bricks");
    fillBricks(grid, *bricks, volume);
    VASTRAY_TRY(setTransform(where, grid.transform(), volume));
    computeVolumeMajorants(volume);
    volume.material = material;
    if (const std::string problem = checkVolume(volume); !problem.empty())
        return Status::error(where + "the volume read is not sound: " + problem);
    return volume;
}

// The emission grid's voxels in the density's bricks (its inactive values count as 0): the same
// transform as the density's, values finite and in [0, kMaxVolumeDensity] (a temperature grid's
// in [0, kMaxTemperature]).
Status readEmission(const std::string& where, const FloatGrid& grid, const std::string& densityName, Volume& volume) {
    Volume placed;
    VASTRAY_TRY(setTransform(where, grid.transform(), placed));
    if (placed.indexToWorld != volume.indexToWorld)
        return Status::error(where + "its transform is not the density grid " + quoted(densityName) +
                             "'s; an emission grid must share the density's voxels");
    volume.emissionVoxels.assign(volume.voxels.size(), 0.0f);
    // Unregistered: a registered accessor enters the tree's TBB hash map, whose header UBSan
    // reports (a misaligned downcast inside TBB); the grid is not written while it is read.
    FloatGrid::ConstUnsafeAccessor access = grid.getConstUnsafeAccessor();
    const int32_t size = int32_t(kVolumeBrickSize);
    for (uint32_t z = 0; z < volume.brickCells[2]; ++z)
        for (uint32_t y = 0; y < volume.brickCells[1]; ++y)
            for (uint32_t x = 0; x < volume.brickCells[0]; ++x) {
                const uint32_t brick = volume.brickOf[x + volume.brickCells[0] * (y + uint64_t(volume.brickCells[1]) * z)];
                if (brick == kNoBrick) continue;
                float* voxels = &volume.emissionVoxels[uint64_t(brick) * kVolumeBrickVoxels];
                const Coord first(volume.origin[0] + size * int32_t(x), volume.origin[1] + size * int32_t(y),
                                  volume.origin[2] + size * int32_t(z));
                for (int32_t k = 0; k < size; ++k)
                    for (int32_t j = 0; j < size; ++j)
                        for (int32_t i = 0; i < size; ++i) {
                            const Coord c = first.offsetBy(i, j, k);
                            float value = 0.0f;
                            if (!access.probeValue(c, value)) continue;
                            if (!isDensity(value))
                                return Status::error(where + "voxel " + coordText(c) + " has the value " +
                                                     numberText(value) + "; emission values are finite and in [0, " +
                                                     numberText(kMaxVolumeDensity) + "]");
                            if (volume.material.temperature && !(value <= kMaxTemperature))
                                return Status::error(where + "voxel " + coordText(c) + " has the temperature " +
                                                     numberText(value) + " K; temperatures are in [0, " +
                                                     numberText(kMaxTemperature) + "] K");
                            voxels[i + size * (j + size * k)] = value;
                        }
            }
    return Status::ok();
}

Result<Volume> readVolume(const std::string& path, const std::string& fileName, uint64_t fileSize,
                          const std::string& gridName, const VolumeMaterial& material, const std::string& emissionName) {
    VdbArchive archive(path, fileSize);
    std::vector<VdbEntry> entries;
    VASTRAY_TRY(archive.scan(fileName, entries));
    auto entry = selectGrid(fileName, entries, gridName);
    if (!entry) return entry.status();
    auto grid = archive.read(fileName, entries, **entry);
    if (!grid) return grid.status();
    const std::string name = (*entry)->name();
    auto volume = volumeOf(fileName + ": grid " + quoted(name) + ": ",
                           *openvdb::gridPtrCast<FloatGrid>(*grid), material);
    if (!volume) return volume;
    volume->name = validUtf8(name);
    if (!emissionName.empty()) {
        auto emissionEntry = selectGrid(fileName, entries, emissionName);
        if (!emissionEntry) return emissionEntry.status();
        auto emission = archive.read(fileName, entries, **emissionEntry);
        if (!emission) return emission.status();
        const char* kind = material.temperature ? ": temperature grid " : ": emission grid ";
        VASTRAY_TRY(readEmission(fileName + kind + quoted((*emissionEntry)->name()) + ": ",
                                 *openvdb::gridPtrCast<FloatGrid>(*emission), name, *volume));
        if (const std::string problem = checkVolume(*volume); !problem.empty())
            return errorIn(fileName, "the volume read is not sound: " + problem);
    }
    return volume;
}

}  // namespace

Result<Volume> readVdbVolume(const std::string& path, const std::string& gridName,
                             const VolumeMaterial& material, const std::string& emissionGrid) {
    const std::string fileName = import::fileNameOf(path);
    auto size = checkedFileSize(path, fileName);
    if (!size) return size.status();
    try {
        initializeOpenVdb();
        return readVolume(path, fileName, *size, gridName, material, emissionGrid);
    } catch (const std::ios_base::failure&) {
        return errorIn(fileName, "ends before the data it describes (truncated or corrupt OpenVDB file)");
    } catch (const std::bad_alloc&) {
        return errorIn(
            fileName,
            "out of memory while reading the OpenVDB file (corrupt, or too large for this machine)");
    } catch (const std::exception& e) {  // openvdb::Exception and the rest
        return errorIn(fileName, std::string("not a readable OpenVDB file: ") + e.what());
    } catch (...) {
        return errorIn(fileName, "not a readable OpenVDB file (unknown error)");
    }
}

}  // namespace vastray

// OpenVDB float grids into vastray volumes (VolumeImport.h). The only translation unit of the
// product that includes OpenVDB (with VdbGridVoxels.h): its headers take ~25 s to compile.
// A volume is opened in one pass over its grids (every value checked, the cell table and each
// brick's largest value found, each leaf's voxels read and dropped); its bricks are then filled
// one at a time from the file when asked for (VdbBrickSource), so that importing holds the cell
// table and per-brick sources, never the voxels (docs/PACKAGE_FORMAT.md, "Volumes").
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
#include <cstring>
#include <fstream>
#include <ios>
#include <memory>
#include <mutex>
#include <new>
#include <vector>

#include "import/ImportCommon.h"
#include "import/VdbGridVoxels.h"
#include "vastray/core/Blackbody.h"
#include "vastray/core/ByteSize.h"
#include "vastray/core/Utf8.h"
#include "vastray/core/VolumeLeaf.h"
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
        auto parent = parentOf(fileName, entries, entry);
        if (!parent) return parent.status();
        grid->setTree(gridOf(**parent)->baseTreePtr());  // throws when the trees' types differ
        return grid;
    }

    // The float grid of `entry` with its voxels left in the file (vdb::GridVoxels); in a file
    // without grid offsets (written to a stream) the grid as scan read it, whole.
    Result<std::unique_ptr<vdb::GridVoxels>> voxels(const std::string& path, const std::string& fileName,
                                                    const std::vector<VdbEntry>& entries, const VdbEntry& entry) {
        if (!inputHasGridOffsets()) {
            auto grid = read(fileName, entries, entry);
            if (!grid) return grid.status();
            return std::make_unique<vdb::GridVoxels>(openvdb::gridPtrCast<FloatGrid>(*grid));
        }
        const GridDescriptor* parent = nullptr;
        if (entry.descriptor.isInstance()) {
            auto p = parentOf(fileName, entries, entry);
            if (!p) return p.status();
            parent = &(*p)->descriptor;
        }
        return std::make_unique<vdb::GridVoxels>(path, entry.descriptor, parent);
    }

private:
    Result<const VdbEntry*> parentOf(const std::string& fileName, const std::vector<VdbEntry>& entries,
                                     const VdbEntry& entry) const {
        const auto parent = std::find_if(entries.begin(), entries.end(), [&](const VdbEntry& e) {
            return e.descriptor.uniqueName() == entry.descriptor.instanceParentName();
        });
        if (parent == entries.end() || parent->descriptor.isInstance())
            return errorIn(fileName,
                           "grid " + quoted(entry.name()) + " is an instance of " +
                               quoted(GridDescriptor::nameAsString(entry.descriptor.instanceParentName())) +
                               ", which the file does not hold as a grid of its own");
        return &*parent;
    }
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

// readVdbVolume's failures that OpenVDB reports by throwing, as errors naming the file.
template <typename F>
auto guardedVdbCall(const std::string& fileName, F&& call) -> decltype(call()) {
    try {
        return call();
    } catch (const std::ios_base::failure&) {
        return errorIn(fileName, "ends before the data it describes (truncated or corrupt OpenVDB file)");
    } catch (const std::bad_alloc&) {
        return errorIn(fileName,
                       "out of memory while reading the OpenVDB file (corrupt, or too large for this machine)");
    } catch (const std::exception& e) {  // openvdb::Exception and the rest
        return errorIn(fileName, std::string("not a readable OpenVDB file: ") + e.what());
    } catch (...) {
        return errorIn(fileName, "not a readable OpenVDB file (unknown error)");
    }
}

// The brick cell holding index-space voxel c, or kNoCell when c lies outside the brick grid.
constexpr uint64_t kNoCell = ~uint64_t(0);
uint64_t cellOf(const Volume& v, const Coord& c) {
    uint64_t cell[3];
    for (int a = 0; a < 3; ++a) {
        const int64_t offset = int64_t(c[a]) - v.origin[a];
        if (offset < 0 || offset >= int64_t(kVolumeBrickSize) * v.brickCells[a]) return kNoCell;
        cell[a] = uint64_t(offset) / kVolumeBrickSize;
    }
    return cell[0] + v.brickCells[0] * (cell[1] + uint64_t(v.brickCells[1]) * cell[2]);
}

// Calls visit(cell) for every brick cell of an active tile's box inside the brick grid (tiles are
// 128 or more voxels a side, aligned to their size, so they cover whole cells), in cell order.
template <typename Visit>
void forTileCells(const Volume& v, const CoordBBox& tile, Visit&& visit) {
    int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        const int64_t size = kVolumeBrickSize, last = int64_t(v.brickCells[a]) - 1;
        lo[a] = std::max<int64_t>(0, (int64_t(tile.min()[a]) - v.origin[a]) / size);
        hi[a] = std::min<int64_t>(last, (int64_t(tile.max()[a]) - v.origin[a]) / size);
        if (int64_t(tile.max()[a]) < v.origin[a] || lo[a] > hi[a]) return;
    }
    const uint64_t nx = v.brickCells[0], nxy = nx * v.brickCells[1];
    for (int64_t z = lo[2]; z <= hi[2]; ++z)
        for (int64_t y = lo[1]; y <= hi[1]; ++y)
            for (int64_t x = lo[0]; x <= hi[0]; ++x) visit(uint64_t(x) + nx * uint64_t(y) + nxy * uint64_t(z));
}

// The active tiles above the leaves (the leaves' voxels are read leaf by leaf).
FloatGrid::TreeType::ValueOnCIter activeTiles(const FloatGrid& grid) {
    FloatGrid::TreeType::ValueOnCIter it = grid.tree().cbeginValueOn();
    it.setMaxDepth(FloatGrid::TreeType::ValueOnCIter::LEAF_DEPTH - 1);
    return it;
}

// Where a stored brick's voxels come from in one grid: a leaf (GridVoxels::leafSource), an
// active tile's value (kTileSource | its bits), or nothing (kNoSource: every voxel 0).
constexpr uint64_t kTileSource = uint64_t(1) << 63;
constexpr uint64_t kNoSource = ~uint64_t(0);
uint64_t tileSource(float value) {
    uint32_t bits;
    std::memcpy(&bits, &value, 4);
    return kTileSource | bits;
}

// Our brick layout (x fastest) from OpenVDB's leaf offset (z fastest).
uint32_t brickIndex(openvdb::Index offset) {
    const Coord c = vdb::FloatLeaf::offsetToLocalCoord(offset);
    return uint32_t(c.x()) + kVolumeBrickSize * (uint32_t(c.y()) + kVolumeBrickSize * uint32_t(c.z()));
}

// A brick's voxels from `source` of grid `g` (kVolumeBrickVoxels values; inactive ones are 0).
void fillBrick(vdb::GridVoxels& g, uint64_t source, float* out) {
    if (source == kNoSource || (source & kTileSource)) {
        const uint32_t bits = source == kNoSource ? 0u : uint32_t(source);
        float value;
        std::memcpy(&value, &bits, 4);
        std::fill(out, out + kVolumeBrickVoxels, value);
        return;
    }
    float values[vdb::FloatLeaf::SIZE];
    vdb::LeafMask mask;
    g.readLeaf(source, values, mask);
    std::fill(out, out + kVolumeBrickVoxels, 0.0f);
    for (auto on = mask.beginOn(); on; ++on) out[brickIndex(on.pos())] = values[on.pos()];
}

// The nonzero leaves of a density grid: the cell each lies in (each leaf, 8^3 voxels 8-aligned,
// lies in one) and where its voxels come from.
struct LeafCell {
    uint64_t cell, source;
};

// Checks every active value, marks the cells holding a nonzero one (kMarkedCell) and records in
// volume.majorant each marked cell's largest value; returns how many cells it marked. Reads each
// leaf's voxels once, in the file's order, and keeps none.
Result<uint64_t> markCells(const std::string& where, vdb::GridVoxels& g, Volume& volume,
                           std::vector<LeafCell>& leaves) {
    volume.brickOf.assign(volume.cellCount(), kNoBrick);
    volume.majorant.assign(volume.cellCount(), 0.0f);
    uint64_t marked = 0;
    auto mark = [&](uint64_t cell, float largest) {
        marked += volume.brickOf[cell] != kMarkedCell;
        volume.brickOf[cell] = kMarkedCell;
        volume.majorant[cell] = largest;
    };
    float values[vdb::FloatLeaf::SIZE];
    vdb::LeafMask mask;
    for (auto leaf = g.grid().tree().cbeginLeaf(); leaf; ++leaf) {
        const uint64_t source = g.leafSource(*leaf);
        g.readLeaf(source, values, mask);
        float largest = 0.0f;
        for (auto on = mask.beginOn(); on; ++on) {
            const float x = values[on.pos()];
            if (!isDensity(x)) return densityError(where, "voxel " + coordText(leaf->offsetToGlobalCoord(on.pos())), x);
            largest = std::max(largest, x);
        }
        if (largest == 0.0f) continue;
        const uint64_t cell = cellOf(volume, leaf->origin());
        assert(cell != kNoCell);
        mark(cell, largest);
        leaves.push_back({cell, source});
    }
    for (auto tile = activeTiles(g.grid()); tile; ++tile) {
        if (!tile.isTileValue()) continue;
        CoordBBox box;
        tile.getBoundingBox(box);
        if (!isDensity(*tile))
            return densityError(where, "tile " + coordText(box.min()) + " to " + coordText(box.max()), *tile);
        if (*tile != 0.0f) forTileCells(volume, box, [&](uint64_t cell) { mark(cell, *tile); });
    }
    return marked;
}

// Numbers the marked cells' bricks in cell order; returns each brick's source in the grid and
// fills `brickMax` with each brick's largest value.
std::vector<uint64_t> numberBricks(const vdb::GridVoxels& g, const std::vector<LeafCell>& leaves, uint64_t bricks,
                                   Volume& volume, std::vector<float>& brickMax) {
    brickMax.assign(bricks, 0.0f);
    uint32_t next = 0;
    for (uint64_t cell = 0; cell < volume.brickOf.size(); ++cell)
        if (volume.brickOf[cell] == kMarkedCell) brickMax[next] = volume.majorant[cell], volume.brickOf[cell] = next++;
    std::vector<uint64_t> sources(bricks, kNoSource);
    for (const LeafCell& leaf : leaves) sources[volume.brickOf[leaf.cell]] = leaf.source;
    for (auto tile = activeTiles(g.grid()); tile; ++tile) {
        if (!tile.isTileValue() || *tile == 0.0f) continue;
        CoordBBox box;
        tile.getBoundingBox(box);
        forTileCells(volume, box, [&](uint64_t cell) { sources[volume.brickOf[cell]] = tileSource(*tile); });
    }
    return sources;
}

bool emissionOk(float value, bool temperature) { return isDensity(value) && (!temperature || value <= kMaxTemperature); }

// An emission (or temperature) value's fault, or an empty string: finite, in [0, 1e18] and for
// a temperature at most kMaxTemperature kelvin.
std::string emissionFault(const std::string& voxel, float value, bool temperature) {
    if (!isDensity(value))
        return voxel + " has the value " + numberText(value) + "; emission values are finite and in [0, " +
               numberText(kMaxVolumeDensity) + "]";
    if (temperature && !(value <= kMaxTemperature))
        return voxel + " has the temperature " + numberText(value) + " K; temperatures are in [0, " +
               numberText(kMaxTemperature) + "] K";
    return {};
}

// The emission grid's sources for the density's bricks (its values where the density has no
// brick are dropped), every value that lands in a brick checked. Of several bad values the one
// reported is the first in brick-cell order, then x fastest within the cell: the order in which
// the bricks are filled.
Result<std::vector<uint64_t>> emissionSources(const std::string& where, vdb::GridVoxels& g, const Volume& volume) {
    std::vector<uint64_t> sources(volume.bricks.count, kNoSource);  // the source is not set yet
    uint64_t firstKey = ~uint64_t(0);
    std::string firstFault;
    auto consider = [&](uint64_t cell, uint32_t index, const Coord& c, float value) {
        const uint64_t key = cell * kVolumeBrickVoxels + index;
        if (key >= firstKey || emissionOk(value, volume.material.temperature)) return;
        firstKey = key;
        firstFault = emissionFault("voxel " + coordText(c), value, volume.material.temperature);
    };
    float values[vdb::FloatLeaf::SIZE];
    vdb::LeafMask mask;
    for (auto leaf = g.grid().tree().cbeginLeaf(); leaf; ++leaf) {
        const uint64_t source = g.leafSource(*leaf);
        g.readLeaf(source, values, mask);  // read in turn: the next leaf's source is where this one ends
        const uint64_t cell = cellOf(volume, leaf->origin());
        if (cell == kNoCell || volume.brickOf[cell] == kNoBrick) continue;
        sources[volume.brickOf[cell]] = source;
        for (auto on = mask.beginOn(); on; ++on)
            consider(cell, brickIndex(on.pos()), leaf->offsetToGlobalCoord(on.pos()), values[on.pos()]);
    }
    for (auto tile = activeTiles(g.grid()); tile; ++tile) {
        if (!tile.isTileValue()) continue;
        CoordBBox box;
        tile.getBoundingBox(box);
        forTileCells(volume, box, [&](uint64_t cell) {
            if (volume.brickOf[cell] == kNoBrick) return;
            sources[volume.brickOf[cell]] = tileSource(*tile);
            const std::array<int32_t, 3> o = volumeCellOrigin(volume, cell);
            consider(cell, 0, Coord(o[0], o[1], o[2]), *tile);
        });
    }
    if (!firstFault.empty()) return Status::error(where + firstFault);
    return sources;
}

// The bricks of a volume whose voxels stay in its .vdb file: each brick is filled from the
// density (and emission) grid's leaf or tile when asked for, and checked again (the file may
// have changed since it was scanned). Called from any thread: one brick at a time.
class VdbBrickSource final : public VolumeBrickSource {
public:
    struct Grid {
        std::string where;  // "fog.vdb: grid 'density': "
        std::unique_ptr<vdb::GridVoxels> voxels;
        std::vector<uint64_t> sources;  // per brick
    };
    VdbBrickSource(std::string fileName, Grid density, Grid emission, bool temperature)
        : fileName_(std::move(fileName)), density_(std::move(density)), emission_(std::move(emission)),
          temperature_(temperature) {}

    Status readBrick(uint32_t volume, uint32_t brick, float* density, float* emission, uint8_t*) const override {
        if (volume != 0 || brick >= density_.sources.size())
            return errorIn(fileName_, "volume " + std::to_string(volume) + " brick " + std::to_string(brick) +
                                          " does not exist (1 volume of " +
                                          std::to_string(density_.sources.size()) + " bricks)");
        std::lock_guard<std::mutex> lock(mutex_);
        return guardedVdbCall(fileName_, [&]() -> Status {
            fillBrick(*density_.voxels, density_.sources[brick], density);
            for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i)
                if (!isDensity(density[i]))
                    return densityError(density_.where, "brick " + std::to_string(brick) + " voxel " + std::to_string(i),
                                        density[i]);
            if (!emission_.voxels) return Status::ok();
            fillBrick(*emission_.voxels, emission_.sources[brick], emission);
            for (uint32_t i = 0; i < kVolumeBrickVoxels; ++i)
                if (!emissionOk(emission[i], temperature_))
                    return Status::error(emission_.where + emissionFault("brick " + std::to_string(brick) + " voxel " +
                                                                             std::to_string(i),
                                                                         emission[i], temperature_));
            return Status::ok();
        });
    }

private:
    std::string fileName_;
    Grid density_, emission_;
    bool temperature_;
    mutable std::mutex mutex_;  // the grids' streams
};

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

// The density grid's brick grid, cell table and majorants, and each brick's source (the voxels
// are read and checked once here, and again when each brick is asked for).
Result<Volume> volumeOf(const std::string& where, vdb::GridVoxels& g, const VolumeMaterial& material,
                        std::vector<uint64_t>& sources) {
    const FloatGrid& grid = g.grid();
    if (!(grid.background() == 0.0f))
        return Status::error(where + "background " + numberText(grid.background()) +
                             " is not 0; vastray reads fog volumes (a level set has a nonzero background)");
    CoordBBox box;
    if (!grid.tree().evalActiveVoxelBoundingBox(box))
        return Status::error(where + "has no active values (an empty grid)");
    Volume volume;
    VASTRAY_TRY(setBrickGrid(where, box, volume));
    std::vector<LeafCell> leaves;
    auto bricks = markCells(where, g, volume, leaves);
    if (!bricks) return bricks.status();
    if (*bricks > kMaxVolumeBricks)
        return Status::error(where + std::to_string(*bricks) +
                             " brick cells hold nonzero values, more than the limit of " +
                             std::to_string(kMaxVolumeBricks) + " bricks");
    std::vector<float> brickMax;
    sources = numberBricks(g, leaves, *bricks, volume, brickMax);
    VASTRAY_TRY(setTransform(where, grid.transform(), volume));
    computeVolumeMajorants(volume, brickMax);
    volume.material = material;
    volume.bricks.count = *bricks;
    return volume;
}

// The emission grid's sources in the density's bricks: the same transform as the density's,
// values finite and in [0, kMaxVolumeDensity] (a temperature grid's in [0, kMaxTemperature]).
Result<std::vector<uint64_t>> readEmission(const std::string& where, vdb::GridVoxels& g,
                                           const std::string& densityName, const Volume& volume) {
    Volume placed;
    VASTRAY_TRY(setTransform(where, g.grid().transform(), placed));
    if (placed.indexToWorld != volume.indexToWorld)
        return Status::error(where + "its transform is not the density grid " + quoted(densityName) +
                             "'s; an emission grid must share the density's voxels");
    return emissionSources(where, g, volume);
}

Result<Volume> openVolume(const std::string& path, const std::string& fileName, uint64_t fileSize,
                          const std::string& gridName, const VolumeMaterial& material, const std::string& emissionName) {
    VdbArchive archive(path, fileSize);
    std::vector<VdbEntry> entries;
    VASTRAY_TRY(archive.scan(fileName, entries));
    auto entry = selectGrid(fileName, entries, gridName);
    if (!entry) return entry.status();
    const std::string name = (*entry)->name();
    VdbBrickSource::Grid density{fileName + ": grid " + quoted(name) + ": ", nullptr, {}};
    auto densityVoxels = archive.voxels(path, fileName, entries, **entry);
    if (!densityVoxels) return densityVoxels.status();
    density.voxels = std::move(densityVoxels).value();
    auto volume = volumeOf(density.where, *density.voxels, material, density.sources);
    if (!volume) return volume;
    density.voxels->dropTopology();  // before the emission grid's is read
    volume->name = validUtf8(name);
    VdbBrickSource::Grid emission;
    if (!emissionName.empty()) {
        auto emissionEntry = selectGrid(fileName, entries, emissionName);
        if (!emissionEntry) return emissionEntry.status();
        const char* kind = material.temperature ? ": temperature grid " : ": emission grid ";
        emission.where = fileName + kind + quoted((*emissionEntry)->name()) + ": ";
        auto emissionVoxels = archive.voxels(path, fileName, entries, **emissionEntry);
        if (!emissionVoxels) return emissionVoxels.status();
        emission.voxels = std::move(emissionVoxels).value();
        auto sources = readEmission(emission.where, *emission.voxels, name, *volume);
        if (!sources) return sources.status();
        emission.sources = std::move(sources).value();
        emission.voxels->dropTopology();
    }
    volume->bricks.emission = emission.voxels != nullptr;
    volume->bricks.source = std::make_shared<VdbBrickSource>(fileName, std::move(density), std::move(emission),
                                                             material.temperature);
    if (const std::string problem = checkVolume(*volume); !problem.empty())
        return errorIn(fileName, "grid " + quoted(name) + ": the volume read is not sound: " + problem);
    return volume;
}

}  // namespace

Result<Volume> openVdbVolume(const std::string& path, const std::string& gridName, const VolumeMaterial& material,
                             const std::string& emissionGrid) {
    const std::string fileName = import::fileNameOf(path);
    auto size = checkedFileSize(path, fileName);
    if (!size) return size.status();
    return guardedVdbCall(fileName, [&]() -> Result<Volume> {
        initializeOpenVdb();
        return openVolume(path, fileName, *size, gridName, material, emissionGrid);
    });
}

Status readVolumeIntoMemory(Volume& volume) {
    const uint64_t bricks = volume.brickCount();
    const bool emission = volume.hasEmission();
    std::vector<float> voxels(bricks * kVolumeBrickVoxels), glow(emission ? voxels.size() : 0);
    // A quantized codec: the values its leaves decode to (those a package of it would hold).
    const std::vector<std::array<int32_t, 3>> origins =
        volume.codec == VolumeCodec::Float ? std::vector<std::array<int32_t, 3>>{} : volumeBrickOrigins(volume);
    std::vector<uint8_t> leaves(2 * kMaxVolumeLeafBytes);
    for (uint64_t b = 0; b < bricks; ++b) {
        float* density = &voxels[b * kVolumeBrickVoxels];
        float* glowing = emission ? &glow[b * kVolumeBrickVoxels] : nullptr;
        if (origins.empty())
            VASTRAY_TRY(readVolumeBrick(volume, b, density, glowing));
        else
            VASTRAY_TRY(readVolumeLeaves(volume, volume.codec, b, origins[b], density, glowing, leaves.data()));
    }
    volume.voxels = std::move(voxels);
    volume.emissionVoxels = std::move(glow);
    volume.bricks = {};
    volume.codec = VolumeCodec::Float;  // in memory: exact
    return Status::ok();
}

Result<Volume> readVdbVolume(const std::string& path, const std::string& gridName,
                             const VolumeMaterial& material, const std::string& emissionGrid) {
    auto volume = openVdbVolume(path, gridName, material, emissionGrid);
    if (!volume) return volume;
    VASTRAY_TRY(readVolumeIntoMemory(*volume));
    if (const std::string problem = checkVolume(*volume); !problem.empty())
        return errorIn(import::fileNameOf(path), "the volume read is not sound: " + problem);
    return volume;
}

}  // namespace vastray

#pragma once
// One float grid of a .vdb file with its voxels left in the file: the grid's metadata, transform
// and topology (its nodes, active tiles and the leaves' value masks; no voxel buffers) are read
// once, and a leaf's voxels are read from the file each time they are asked for. This is the
// delayed loading that openvdb::io::File does through a memory map, done on a stream of our own:
// every short read throws (std::ios_base::failure) as VdbArchive's does, the file's pages are not
// charged to the process, and a leaf read for one brick is dropped once the brick is filled (File
// keeps every leaf it has loaded). Included by VdbVolume.cpp only (OpenVDB stays in one
// translation unit). Throws what OpenVDB throws; the caller turns it into an error.
#include <openvdb/io/Archive.h>
#include <openvdb/io/Compression.h>
#include <openvdb/io/GridDescriptor.h>
#include <openvdb/io/io.h>
#include <openvdb/openvdb.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

namespace vastray::vdb {

using FloatLeaf = openvdb::FloatGrid::TreeType::LeafNodeType;
using LeafMask = FloatLeaf::NodeMaskType;

class GridVoxels : public openvdb::io::Archive {
public:
    // A grid read whole (a file written to a stream has no grid offsets, so its grids are read as
    // they come): its leaves hold their voxels, and a leaf's "source" is its address.
    explicit GridVoxels(openvdb::FloatGrid::Ptr whole) : grid_(std::move(whole)), whole_(true) {}

    // Grid `grid` of the file at `path` (an instance: `parent` is the grid whose tree it shares),
    // its tree read without voxel buffers. Files of format 221 and older (OpenVDB 2 and before)
    // keep a leaf's origin beside its buffer: those grids are read whole.
    GridVoxels(const std::string& path, const openvdb::io::GridDescriptor& grid,
               const openvdb::io::GridDescriptor* parent)
        : in_(path, std::ios::binary) {
        in_.exceptions(std::ios::failbit | std::ios::badbit);
        readHeader(in_);
        fileMetadata_ = std::make_shared<openvdb::io::StreamMetadata>();
        fileMetadata_->setSeekable(true);
        openvdb::io::setStreamMetadataPtr(in_, fileMetadata_, /*transfer=*/false);
        setFormatVersion(in_);
        setLibraryVersion(in_);
        setDataCompression(in_);
        whole_ = openvdb::io::getFormatVersion(in_) < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION;
        openvdb::GridBase::Ptr g = readPart(grid);
        if (parent) g->setTree(readPart(*parent)->baseTreePtr());  // throws when the trees' types differ
        grid_ = openvdb::gridPtrCast<openvdb::FloatGrid>(g);
        if (!grid_) OPENVDB_THROW(openvdb::TypeError, "the grid's tree is not a float tree");
        // The tree's background, which the stream points at, goes with the tree (dropTopology).
        background_ = grid_->background();
        openvdb::io::setGridBackgroundValuePtr(in_, &background_);
    }

    const openvdb::FloatGrid& grid() const { return *grid_; }
    bool whole() const { return whole_; }

    // Where the voxels of `leaf`, the next leaf of a walk in the tree's order (cbeginLeaf), come
    // from: the file offset of its buffer, which must be read (readLeaf) before the next leaf's
    // source is asked for; in a grid read whole, the leaf's address.
    uint64_t leafSource(const FloatLeaf& leaf) const {
        return whole_ ? uint64_t(reinterpret_cast<uintptr_t>(&leaf)) : uint64_t(next_);
    }

    // The leaf's voxels (OpenVDB's order: offset = x * 64 + y * 8 + z) and which are active.
    void readLeaf(uint64_t source, float* values, LeafMask& mask) {
        if (whole_) {
            const FloatLeaf& leaf = *reinterpret_cast<const FloatLeaf*>(uintptr_t(source));
            mask = leaf.valueMask();
            std::memcpy(values, leaf.buffer().data(), sizeof(float) * FloatLeaf::SIZE);
            return;
        }
        if (std::streamoff(source) != next_) in_.seekg(std::streamoff(source));
        // A leaf's buffer holds its value mask again, then its values: as OpenVDB's delayed
        // loading (LeafBuffer::doLoad) reads it.
        mask.load(in_);
        openvdb::io::readCompressedValues(in_, values, FloatLeaf::SIZE, mask, fromHalf_);
        next_ = in_.tellg();
    }

    // Frees the tree (its nodes and masks) of a grid whose voxels stay in the file: the sources
    // taken from it stay valid. A grid read whole keeps its tree (its sources are its leaves).
    void dropTopology() {
        if (!whole_) grid_.reset();
    }

private:
    // Grid `d`'s metadata and transform, and unless it is an instance its topology; the stream
    // then stands at its first leaf's buffer. As Archive::readGrid does it, less readBuffers.
    openvdb::GridBase::Ptr readPart(const openvdb::io::GridDescriptor& d) {
        openvdb::GridBase::Ptr grid = openvdb::GridBase::createGrid(d.gridType());
        grid->setSaveFloatAsHalf(d.saveFloatAsHalf());
        d.seekToGrid(in_);
        if (whole_) {
            Archive::readGrid(grid, d, in_);
            return grid;
        }
        readGridCompression(in_);
        gridMetadata_ = std::make_shared<openvdb::io::StreamMetadata>(*fileMetadata_);
        gridMetadata_->setHalfFloat(grid->saveFloatAsHalf());
        openvdb::io::setStreamMetadataPtr(in_, gridMetadata_, /*transfer=*/false);
        openvdb::io::setGridClass(in_, openvdb::GRID_UNKNOWN);
        openvdb::io::setGridBackgroundValuePtr(in_, nullptr);
        grid->readMeta(in_);
        gridMetadata_->gridMetadata() = static_cast<openvdb::MetaMap&>(*grid);
        openvdb::io::setGridClass(in_, grid->getGridClass());
        grid->readTransform(in_);
        if (!d.isInstance()) {
            grid->readTopology(in_);
            fromHalf_ = d.saveFloatAsHalf();
            next_ = in_.tellg();
        }
        return grid;
    }

    std::ifstream in_;
    openvdb::FloatGrid::Ptr grid_;
    bool whole_ = false;
    bool fromHalf_ = false;
    std::streamoff next_ = 0;  // where the stream stands: the next leaf's buffer in a walk
    float background_ = 0.0f;
    // OpenVDB keeps pointers to these in the stream: they live as long as the stream.
    openvdb::io::StreamMetadata::Ptr fileMetadata_, gridMetadata_;
};

}  // namespace vastray::vdb

#pragma once
// The package's textures (docs/PACKAGE_FORMAT.md, "Textures"): a table of texture records and
// page entries under one checksum, and the pages' bytes, each page a zstd frame of its own
// (TexturePages.h) with its own checksum, so that a render reads and checks only the pages its
// rays ask for. The table is small (96 bytes a texture, 24 a page) and read when a package
// opens; the pages are read on demand.
//
// Table: texture count (u32, at most kMaxPackageTextures), reserved (u32, 0); per texture a
// record of 96 bytes: name (64 bytes of UTF-8, zero-padded), width, height, wrap S, wrap T,
// encoding, level count, page count, first page entry (8 x u32); then per page an entry of 24
// bytes: offset of its frame from the start of the page data (u64), XXH64 of the frame (u64),
// frame bytes (u32), reserved (u32, 0); then the XXH64 of everything before it (u64). A
// texture's pages are its levels' pages in order (core/Texture.h) and its entries follow the
// previous texture's; frames follow each other without gaps in entry order.
#include <cstdint>
#include <string>
#include <vector>

#include "package/TexturePages.h"
#include "vastray/core/Result.h"
#include "vastray/core/Texture.h"

namespace vastray {

constexpr uint32_t kMaxPackageTextures = 4096;
constexpr uint32_t kTextureRecordBytes = 96;
constexpr uint32_t kTexturePageEntryBytes = 24;
constexpr uint32_t kTextureNameBytes = 64;

struct PackageTexture {
    std::string name;
    TextureLayout layout;
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    TextureEncoding encoding = TextureEncoding::Srgb;
    uint32_t firstEntry = 0;  // its level 0 page's entry
};

struct TexturePageEntry {
    uint64_t offset = 0;  // from the start of the page data
    uint64_t checksum = 0;
    uint32_t size = 0;
};

struct TextureTable {
    std::vector<PackageTexture> textures;
    std::vector<TexturePageEntry> entries;
    uint64_t dataBytes = 0;  // the page data's size: the last frame's end
};

// Builds the table and the page data as a writer appends textures: each texture's pages are
// compressed and appended to `data` (the caller writes it out when it likes, e.g. after each
// texture, and clears it: offsets count every byte appended so far).
class TextureSectionWriter {
public:
    Status add(const std::string& name, const TexturePyramid& pyramid);
    std::vector<uint8_t>& data() { return data_; }
    const TextureTable& table() const { return table_; }
    // The table's bytes, checksum last.
    std::vector<uint8_t> tableBytes() const;

private:
    TextureTable table_;
    std::vector<uint8_t> data_;
};

// Reads a table and checks it against itself and against `dataBytes`, the size of the page
// data that follows it in the file: count and reserved words, the checksum, each record's size
// (within kMaxTextureSide), wrap modes and encoding, its level and page counts against the
// layout its size gives, its first entry, each entry's frame inside the data, in order and
// without gaps, of a size zstd could have written. Errors name `fileName`, the texture (by
// index and name) or the entry and what was wrong. Names are repaired as camera names are.
// `tableBytes` is set to the table's size (what the next section's offset is checked against).
Result<TextureTable> parseTextureTable(const uint8_t* data, size_t size, uint64_t dataBytes,
                                       const std::string& fileName, uint64_t& tableBytes);

// One page: `frame` is the entry's bytes read from the page data. Checks the checksum, then
// inflates into `page` (kTexturePageBytes). Errors name the file, the texture and the page.
Status readTexturePage(const TextureTable& table, uint32_t texture, uint32_t page, const uint8_t* frame,
                       size_t frameBytes, uint8_t* out, const std::string& fileName);

}  // namespace vastray

#pragma once
// The package's textures (docs/PACKAGE_FORMAT.md, "Textures", version 10): a head of 32 bytes
// right after the lights section (texture count, reserved, the table's offset and size, the
// XXH64 of those 24 bytes); then, at the end of the file, the page data (each page a zstd frame
// of its own, TexturePages.h, with its own checksum, so that a render reads and checks only the
// pages its rays ask for) and after it the table: per texture a record of 96 bytes (name, 64
// bytes of UTF-8, zero-padded; width, height, wrap S, wrap T, encoding, level count, page count,
// first page entry: 8 x u32), per page an entry of 24 bytes (offset of its frame from the start
// of the page data (u64), XXH64 of the frame (u64), frame bytes (u32), reserved (u32, 0)), then
// the XXH64 of the records and entries. A texture's pages are its levels' pages in order
// (core/Texture.h), its entries follow the previous texture's, frames follow each other without
// gaps in entry order, and the table ends the file. The writer knows the table only once every
// page is compressed, hence the head that points to it.
#include <cstdint>
#include <string>
#include <vector>

#include "package/TexturePages.h"
#include "vastray/core/Result.h"
#include "vastray/core/Texture.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray {

constexpr uint32_t kMaxPackageTextures = 4096;
constexpr uint32_t kTextureRecordBytes = 96;
constexpr uint32_t kTexturePageEntryBytes = 24;
constexpr uint32_t kTextureNameBytes = 64;

constexpr uint32_t kTextureHeadBytes = 32;

// The head: where the table lies. Without textures: count 0, offset the end of the file, size 0.
struct TextureHead {
    uint32_t count = 0;
    uint64_t tableOffset = 0, tableBytes = 0;
};
std::vector<uint8_t> serializeTextureHead(const TextureHead& head);
// Checks the checksum, the reserved word, the count's limit, and that the table's size is the
// one `count` textures could have (at least their records and the checksum).
Result<TextureHead> parseTextureHead(const uint8_t* data, size_t size);

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
    // The table's bytes (records, entries, checksum); none without textures.
    std::vector<uint8_t> tableBytes() const;

private:
    TextureTable table_;
    std::vector<uint8_t> data_;
};

// Reads the table of `count` textures (`size` bytes exactly) and checks it against itself and
// against `dataBytes`, the size of the page data before it in the file: the checksum, each record's size
// (within kMaxTextureSide), wrap modes and encoding, its level and page counts against the
// layout its size gives, its first entry, each entry's frame inside the data, in order and
// without gaps, of a size zstd could have written. Errors name `fileName`, the texture (by
// index and name) or the entry and what was wrong. Names are repaired as camera names are.
Result<TextureTable> parseTextureTable(const uint8_t* data, size_t size, uint32_t count, uint64_t dataBytes,
                                       const std::string& fileName);

// One page: `frame` is the entry's bytes read from the page data. Checks the checksum, then
// inflates into `page` (kTexturePageBytes). Errors name the file, the texture and the page.
Status readTexturePage(const std::vector<PackageTexture>& textures, const std::vector<TexturePageEntry>& entries,
                       uint32_t texture, uint32_t page, const uint8_t* frame, size_t frameBytes, uint8_t* out,
                       const std::string& fileName);

}  // namespace vastray

#include "package/TextureSection.h"

#include <zstd.h>

#include "package/ByteIo.h"
#include "vastray/core/Checksum.h"
#include "vastray/core/Utf8.h"

namespace vastray {
namespace {

std::string textureLabel(uint32_t index, const std::string& name) {
    return "texture " + std::to_string(index) + (name.empty() ? "" : " ('" + name + "')");
}

}  // namespace

Status TextureSectionWriter::add(const std::string& name, const TexturePyramid& pyramid) {
    if (table_.textures.size() >= kMaxPackageTextures)
        return Status::error("more than " + std::to_string(kMaxPackageTextures) + " textures in one package");
    if (pyramid.pages.size() != size_t(pyramid.layout.pageCount) * kTexturePageBytes)
        return Status::error(name + ": " + std::to_string(pyramid.pages.size()) + " bytes of pages for " +
                             std::to_string(pyramid.layout.pageCount) + " pages");
    PackageTexture texture;
    texture.name = cutUtf8(name, kTextureNameBytes);
    texture.layout = pyramid.layout;
    texture.wrapS = pyramid.wrapS;
    texture.wrapT = pyramid.wrapT;
    texture.encoding = pyramid.encoding;
    texture.firstEntry = uint32_t(table_.entries.size());
    for (uint32_t p = 0; p < pyramid.layout.pageCount; ++p) {
        const std::vector<uint8_t> frame = encodeTexturePage(pyramid.pages.data() + size_t(p) * kTexturePageBytes);
        if (frame.empty()) return Status::error(name + ": page " + std::to_string(p) + " did not compress");
        table_.entries.push_back({table_.dataBytes, checksum64(frame.data(), frame.size()), uint32_t(frame.size())});
        table_.dataBytes += frame.size();
        data_.insert(data_.end(), frame.begin(), frame.end());
    }
    table_.textures.push_back(std::move(texture));
    return Status::ok();
}

std::vector<uint8_t> TextureSectionWriter::tableBytes() const {
    if (table_.textures.empty()) return {};
    ByteWriter w;
    for (const PackageTexture& t : table_.textures) {
        w.putFixedString(t.name, kTextureNameBytes);
        for (uint32_t v : {t.layout.width, t.layout.height, uint32_t(t.wrapS), uint32_t(t.wrapT), uint32_t(t.encoding),
                           t.layout.levelCount, t.layout.pageCount, t.firstEntry})
            w.put(v);
    }
    for (const TexturePageEntry& e : table_.entries) {
        w.put(e.offset);
        w.put(e.checksum);
        w.put(e.size);
        w.put(uint32_t(0));
    }
    w.put(checksum64(w.bytes().data(), w.size()));
    return std::move(w.bytes());
}

std::vector<uint8_t> serializeTextureHead(const TextureHead& head) {
    ByteWriter w;
    w.put(head.count);
    w.put(uint32_t(0));
    w.put(head.tableOffset);
    w.put(head.tableBytes);
    w.put(checksum64(w.bytes().data(), w.size()));
    return std::move(w.bytes());
}

Result<TextureHead> parseTextureHead(const uint8_t* data, size_t size) {
    ByteReader r(data, size);
    TextureHead head;
    uint32_t reserved = 0;
    uint64_t stored = 0;
    r.get(head.count), r.get(reserved), r.get(head.tableOffset), r.get(head.tableBytes), r.get(stored);
    if (!r.ok()) return Status::error("textures: the head is cut short");
    if (stored != checksum64(data, kTextureHeadBytes - 8)) return Status::error("textures: the head's checksum does not match");
    if (reserved != 0) return Status::error("textures: the head's reserved word " + std::to_string(reserved) + " is not 0");
    if (head.count > kMaxPackageTextures)
        return Status::error("textures: " + std::to_string(head.count) + " textures is more than the " +
                             std::to_string(kMaxPackageTextures) + " a package may hold");
    const uint64_t least = head.count ? uint64_t(head.count) * kTextureRecordBytes + 8 : 0;
    if (head.tableBytes < least || (head.count == 0 && head.tableBytes != 0))
        return Status::error("textures: a table of " + std::to_string(head.tableBytes) + " bytes for " +
                             std::to_string(head.count) + " textures");
    return head;
}

Result<TextureTable> parseTextureTable(const uint8_t* data, size_t size, uint32_t count, uint64_t dataBytes,
                                       const std::string& fileName) {
    auto fail = [&](const std::string& what) { return Status::error(fileName + ": textures: " + what); };
    ByteReader r(data, size);
    if (count > kMaxPackageTextures)
        return fail(std::to_string(count) + " textures is more than the " + std::to_string(kMaxPackageTextures) +
                    " a package may hold");
    if (uint64_t(count) * kTextureRecordBytes > r.remaining()) return fail("the table is cut short");
    TextureTable table;
    table.textures.resize(count);
    uint64_t entries = 0;
    for (uint32_t i = 0; i < count; ++i) {
        PackageTexture& t = table.textures[i];
        std::string name;
        r.getFixedString(name, kTextureNameBytes);
        t.name = validUtf8(name);
        uint32_t v[8];
        for (uint32_t& x : v) r.get(x);
        const std::string label = textureLabel(i, t.name);
        auto layout = makeTextureLayout(v[0], v[1]);
        if (!layout) return fail(label + ": " + layout.message());
        t.layout = *layout;
        if (v[2] > 2 || v[3] > 2) return fail(label + ": wrap modes " + std::to_string(v[2]) + ", " +
                                              std::to_string(v[3]) + " (0 repeat, 1 clamp, 2 mirror)");
        if (v[4] > 1) return fail(label + ": encoding " + std::to_string(v[4]) + " (0 sRGB, 1 linear)");
        t.wrapS = TextureWrap(v[2]);
        t.wrapT = TextureWrap(v[3]);
        t.encoding = TextureEncoding(v[4]);
        if (v[5] != layout->levelCount || v[6] != layout->pageCount)
            return fail(label + ": " + std::to_string(v[5]) + " levels and " + std::to_string(v[6]) +
                        " pages, where " + std::to_string(v[0]) + "x" + std::to_string(v[1]) + " texels have " +
                        std::to_string(layout->levelCount) + " and " + std::to_string(layout->pageCount));
        if (v[7] != entries)
            return fail(label + ": first page entry " + std::to_string(v[7]) + ", not " + std::to_string(entries));
        t.firstEntry = v[7];
        entries += layout->pageCount;
    }
    if (count > 0 && entries * kTexturePageEntryBytes + 8 > r.remaining()) return fail("the table is cut short");
    table.entries.resize(entries);
    const size_t largestFrame = ZSTD_compressBound(kTexturePageBytes);
    for (uint64_t i = 0; i < entries; ++i) {
        TexturePageEntry& e = table.entries[i];
        uint32_t zero = 0;
        r.get(e.offset);
        r.get(e.checksum);
        r.get(e.size);
        r.get(zero);
        const std::string label = "page entry " + std::to_string(i);
        if (zero != 0) return fail(label + ": reserved word " + std::to_string(zero) + " is not 0");
        if (e.offset != table.dataBytes)
            return fail(label + ": offset " + std::to_string(e.offset) + ", where the previous frame ends at " +
                        std::to_string(table.dataBytes));
        if (e.size == 0 || e.size > largestFrame)
            return fail(label + ": a frame of " + std::to_string(e.size) + " bytes (1.." + std::to_string(largestFrame) + ")");
        table.dataBytes += e.size;
        if (table.dataBytes > dataBytes)
            return fail(label + ": its frame ends at " + std::to_string(table.dataBytes) + ", beyond the " +
                        std::to_string(dataBytes) + " bytes of page data");
    }
    const size_t covered = r.position();
    uint64_t stored = 0;
    r.get(stored);
    if (count > 0 && stored != checksum64(data, covered)) return fail("the table's checksum does not match");
    if (r.remaining() != 0 || (count == 0 && size != 0))
        return fail("the table is " + std::to_string(size) + " bytes, its textures' records and entries " +
                    std::to_string(count ? r.position() : 0));
    if (table.dataBytes != dataBytes)
        return fail("the frames end at " + std::to_string(table.dataBytes) + ", the page data at " +
                    std::to_string(dataBytes));
    return table;
}

Status readTexturePage(const std::vector<PackageTexture>& textures, const std::vector<TexturePageEntry>& entries,
                       uint32_t texture, uint32_t page, const uint8_t* frame, size_t frameBytes, uint8_t* out,
                       const std::string& fileName) {
    const PackageTexture& t = textures[texture];
    const TexturePageEntry& e = entries[t.firstEntry + page];
    const std::string where = fileName + ": " + textureLabel(texture, t.name) + " page " + std::to_string(page) + ": ";
    if (frameBytes != e.size)
        return Status::error(where + std::to_string(frameBytes) + " bytes read, the entry says " + std::to_string(e.size));
    if (checksum64(frame, frameBytes) != e.checksum) return Status::error(where + "checksum does not match");
    return decodeTexturePage(frame, frameBytes, out).withContext(where);
}

}  // namespace vastray

#include "import/PlyHeader.h"

#include <cstring>
#include <limits>
#include <optional>

#include "import/ImportCommon.h"
#include "import/TextScan.h"

namespace vastray::import {
namespace {

std::optional<PlyType> typeFromName(std::string_view n) {
    if (n == "char" || n == "int8") return PlyType::Int8;
    if (n == "uchar" || n == "uint8") return PlyType::UInt8;
    if (n == "short" || n == "int16") return PlyType::Int16;
    if (n == "ushort" || n == "uint16") return PlyType::UInt16;
    if (n == "int" || n == "int32") return PlyType::Int32;
    if (n == "uint" || n == "uint32") return PlyType::UInt32;
    if (n == "float" || n == "float32") return PlyType::Float32;
    if (n == "double" || n == "float64") return PlyType::Float64;
    return std::nullopt;
}

class HeaderParser {
public:
    HeaderParser(const std::string& name) : name_(name) {}

    Status line(const char* p, const char* eol, PlyHeader& header) {
        const std::string_view keyword = nextToken(p, eol);
        if (keyword == "format") return format(p, eol, header);
        if (keyword == "element") return element(p, eol, header);
        if (keyword == "property") return property(p, eol, header);
        if (keyword == "comment" && nextToken(p, eol) == "TextureFile") ++header.textureFiles;
        // comment, obj_info, and stray text such as a comment wrapped onto a second line
        // (Blender 2.47 writes those): none of it describes the body.
        return Status::ok();
    }

    Status error(const std::string& message) const {
        return errorIn(name_, "header line " + std::to_string(lineNumber) + ": " + message);
    }

    uint64_t lineNumber = 1;
    bool sawFormat = false;

private:
    Status format(const char* p, const char* eol, PlyHeader& header) {
        const std::string_view f = nextToken(p, eol);
        if (f == "ascii") header.format = PlyFormat::Ascii;
        else if (f == "binary_little_endian") header.format = PlyFormat::BinaryLittleEndian;
        else if (f == "binary_big_endian") header.format = PlyFormat::BinaryBigEndian;
        else return error("unknown format '" + std::string(f) + "'");
        sawFormat = true;
        return Status::ok();
    }

    Status element(const char* p, const char* eol, PlyHeader& header) {
        PlyElement e;
        e.name = std::string(nextToken(p, eol));
        if (e.name.empty() || !parseNumber(p, eol, e.count) || !trimmed(p, eol).empty())
            return error("malformed element statement");
        header.elements.push_back(std::move(e));
        return Status::ok();
    }

    Status property(const char* p, const char* eol, PlyHeader& header) {
        if (header.elements.empty()) return error("property before any element");
        PlyProperty prop;
        std::string_view typeName = nextToken(p, eol);
        if (typeName == "list") {
            prop.isList = true;
            const auto countType = typeFromName(nextToken(p, eol));
            if (!countType || isFloatType(*countType)) return error("bad list count type");
            prop.countType = *countType;
            typeName = nextToken(p, eol);
        }
        const auto type = typeFromName(typeName);
        if (!type) return error("unknown property type '" + std::string(typeName) + "'");
        prop.type = *type;
        prop.name = std::string(nextToken(p, eol));
        if (prop.name.empty()) return error("property without a name");
        header.elements.back().properties.push_back(std::move(prop));
        return Status::ok();
    }

    const std::string& name_;
};

// Refuses counts the body cannot hold, so nothing is ever reserved for a lying header.
Status checkCounts(const PlyHeader& header, uint64_t bodyBytes, const std::string& name) {
    for (const PlyElement& e : header.elements) {
        if (e.name == "vertex" && e.count > std::numeric_limits<uint32_t>::max())
            return errorIn(name, "element vertex count " + std::to_string(e.count) +
                                     " exceeds the uint32 index range");
        if (e.count == 0) continue;
        const uint64_t rowBytes = e.minRowBytes(header.format);
        if (rowBytes == 0) return errorIn(name, "element " + e.name + " has no properties");
        const uint64_t capacity = (bodyBytes + 1) / rowBytes;  // +1: last ASCII row needs no separator
        if (e.count > capacity)
            return errorIn(name, "element " + e.name + " count " + std::to_string(e.count) +
                                     " is larger than the file could hold (" + std::to_string(bodyBytes) +
                                     " body bytes, at least " + std::to_string(rowBytes) + " per row)");
    }
    return Status::ok();
}

}  // namespace

bool PlyElement::hasLists() const {
    for (const PlyProperty& p : properties)
        if (p.isList) return true;
    return false;
}

uint64_t PlyElement::minRowBytes(PlyFormat format) const {
    uint64_t bytes = 0;
    for (const PlyProperty& p : properties) {
        if (format == PlyFormat::Ascii) bytes += 2;  // one digit and one separator
        else bytes += plySize(p.isList ? p.countType : p.type);
    }
    return bytes;
}

Result<PlyHeader> parsePlyHeader(const char* data, size_t size, const std::string& name) {
    const char* end = data + size;
    if (size < 4 || std::memcmp(data, "ply", 3) != 0 || (data[3] != '\n' && data[3] != '\r'))
        return errorIn(name, "not a PLY file (missing 'ply' magic line)");
    PlyHeader header;
    HeaderParser parser(name);
    const char* firstEol = static_cast<const char*>(std::memchr(data, '\n', size));
    if (!firstEol) return errorIn(name, "file ends inside the header (no end_header)");
    const char* p = firstEol + 1;
    for (parser.lineNumber = 2; p < end; ++parser.lineNumber) {
        const char* eol = static_cast<const char*>(std::memchr(p, '\n', end - p));
        if (!eol) return parser.error("file ends inside the header (no end_header)");
        if (trimmed(p, eol) == "end_header") {
            if (!parser.sawFormat) return parser.error("no format statement");
            header.bodyOffset = static_cast<size_t>(eol + 1 - data);
            if (Status s = checkCounts(header, size - header.bodyOffset, name); !s.isOk()) return s;
            return header;
        }
        if (Status s = parser.line(p, eol, header); !s.isOk()) return s;
        p = eol + 1;
    }
    return errorIn(name, "file ends inside the header (no end_header)");
}

}  // namespace vastray::import

#include "import/MtlLibrary.h"

#include <cstring>

#include "import/ImportCommon.h"
#include "import/TextScan.h"

namespace vastray::import {
namespace {

bool parseColor(const char* p, const char* end, std::array<float, 3>& out) {
    for (float& c : out) {
        if (!parseField(p, end, c)) return false;
    }
    return true;
}

}  // namespace

Status parseMtlFile(const std::string& path, MtlLibrary& library) {
    auto bytes = readWholeFile(path);
    if (!bytes) return bytes.status();
    const std::string name = fileNameOf(path);
    const char* p = bytes->data();
    const char* end = p + bytes->size();
    MtlEntry* current = nullptr;
    for (uint64_t line = 1; p < end; ++line) {
        const char* eol = static_cast<const char*>(std::memchr(p, '\n', end - p));
        if (!eol) eol = end;
        const std::string_view keyword = nextToken(p, eol);
        if (keyword == "newmtl") {
            current = &library[std::string(trimmed(p, eol))];
        } else if ((keyword == "Kd" || keyword == "Ke") && current) {
            std::array<float, 3>& target = keyword == "Kd" ? current->diffuse : current->emissive;
            if (!parseColor(p, eol, target))
                return errorIn(name, "line " + std::to_string(line) + ": malformed " +
                                         std::string(keyword) + " colour");
        }
        p = eol + (eol < end ? 1 : 0);
    }
    return Status::ok();
}

}  // namespace vastray::import

#include "import/MtlLibrary.h"

#include <cstring>

#include "import/ImportCommon.h"
#include "import/TextScan.h"

namespace vastray::import {
namespace {

// "r g b", or "r" alone for grey (the MTL spec: g and b default to r; Blender writes "Ks 0").
bool parseColor(const char* p, const char* end, std::array<float, 3>& out) {
    if (!parseField(p, end, out[0])) return false;
    if (trimmed(p, end).empty()) {
        out[1] = out[2] = out[0];
        return true;
    }
    return parseField(p, end, out[1]) && parseField(p, end, out[2]);
}

}  // namespace

Status parseMtlFile(const std::string& path, MtlLibrary& library, MtlUnused& unused) {
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
        } else if ((keyword == "Kd" || keyword == "Ke" || keyword == "Ks") && current) {
            std::array<float, 3>& target =
                keyword == "Kd" ? current->diffuse : (keyword == "Ke" ? current->emissive : current->specular);
            if (!parseColor(p, eol, target))
                return errorIn(name, "line " + std::to_string(line) + ": malformed " +
                                         std::string(keyword) + " colour");
        } else if (keyword == "illum" && current) {
            if (!parseField(p, eol, current->illumination) || current->illumination < 0 || current->illumination > 10)
                return errorIn(name, "line " + std::to_string(line) + ": illum must be an integer in [0, 10]");
        } else if (keyword == "Ns" && current) {
            if (!parseField(p, eol, current->exponent) || !(current->exponent >= 0.0f && current->exponent <= 1e6f))
                return errorIn(name, "line " + std::to_string(line) + ": Ns must be a number in [0, 1e6]");
        } else if (current && (keyword.substr(0, 4) == "map_" || keyword == "bump" || keyword == "norm" ||
                               keyword == "disp" || keyword == "decal" || keyword == "refl")) {
            ++unused["texture maps"];
        } else if (current && (keyword == "d" || keyword == "Tr")) {
            float value = 0.0f;  // opacity (d) or transparency (Tr = 1 - d); a malformed one is left alone
            if (parseField(p, eol, value) && (keyword == "d" ? value < 1.0f : value > 0.0f))
                ++unused["transparency statements (d below 1, Tr above 0)"];
        } else if (current && (keyword == "Pr" || keyword == "Pm" || keyword == "Ps" || keyword == "Pc" ||
                               keyword == "Pcr" || keyword == "aniso" || keyword == "anisor")) {
            ++unused["PBR statements (Pr, Pm, Ps, Pc, Pcr, aniso)"];
        }
        p = eol + (eol < end ? 1 : 0);
    }
    return Status::ok();
}

}  // namespace vastray::import

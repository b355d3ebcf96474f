#include "import/MtlLibrary.h"

#include <algorithm>
#include <cmath>
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

// One to `most` numbers after an option ("-s 2 2"); stops before a token that is not one (the
// file name may start with a digit: "-s 2 2 1.png").
int parseNumbers(const char*& p, const char* end, float* out, int most) {
    int count = 0;
    for (const char* q = p; count < most && parseField(q, end, out[count]); p = q) ++count;
    return count;
}

// The options before a map's file name. -s, -o and -clamp are read; -texres and -type (a
// resolution hint, refl's kind) change nothing; the others change the look and are counted.
// Returns an error message, or "" when the option is good.
std::string parseMapOption(std::string_view option, const char*& p, const char* end, MtlMap& map, MtlUnused& unused) {
    float values[3] = {0.0f, 0.0f, 0.0f};
    const std::string name(option);
    const std::string notRead = "the map is read without it";
    if (option == "-s" || option == "-o" || option == "-t") {
        const int count = parseNumbers(p, end, values, 3);
        if (count == 0) return name + " needs one to three numbers";
        if (option == "-t") return unused.add("map options -t (turbulence)", notRead), "";
        std::array<float, 2>& target = option == "-s" ? map.scale : map.offset;
        target = {values[0], count > 1 ? values[1] : target[1]};
        for (float v : target)
            if (!std::isfinite(v) || std::fabs(v) > kMaxUvTransformValue)
                return name + " value " + std::to_string(v) + " is outside +-1e6";
        return "";
    }
    if (option == "-mm") {
        if (parseNumbers(p, end, values, 2) != 2) return "-mm needs two numbers (base, gain)";
        if (values[0] != 0.0f || values[1] != 1.0f) unused.add("map options -mm (value range)", notRead);
        return "";
    }
    if (option == "-bm" || option == "-boost" || option == "-texres") {
        if (parseNumbers(p, end, values, 1) != 1) return name + " needs a number";
        if (option != "-texres") unused.add("map options " + name, notRead);
        return "";
    }
    const std::string_view value = nextToken(p, end);
    if (value.empty()) return name + " needs a value";
    if (option == "-clamp" || option == "-blendu" || option == "-blendv" || option == "-cc") {
        if (value != "on" && value != "off") return name + " must be on or off";
        if (option == "-clamp") map.clamp = value == "on";
        const bool changesLook = option == "-cc" ? value == "on" : (option != "-clamp" && value == "off");
        if (changesLook) unused.add("map options " + name + " " + std::string(value), notRead);
        return "";
    }
    if (option == "-imfchan") {
        if (value.size() != 1 || std::string_view("rgbmlz").find(value[0]) == std::string_view::npos)
            return "-imfchan must be r, g, b, m, l or z";
        map.channel = value[0];
    }
    return "";  // -imfchan, -type
}

bool isMapOption(std::string_view token) {
    for (const char* known : {"-s", "-o", "-t", "-mm", "-bm", "-boost", "-texres", "-clamp", "-blendu", "-blendv",
                              "-cc", "-imfchan", "-type"})
        if (token == known) return true;
    return false;
}

// "[options] file name": the file is the rest of the line, spaces and all.
std::string parseMap(const char* p, const char* end, MtlMap& map, MtlUnused& unused) {
    for (;;) {
        const char* before = p;
        const std::string_view token = nextToken(p, end);
        if (!isMapOption(token)) {
            p = before;
            break;
        }
        if (std::string problem = parseMapOption(token, p, end, map, unused); !problem.empty()) return problem;
    }
    map.file = std::string(trimmed(p, end));
    return map.file.empty() ? "the map names no file" : "";
}

// map_d's code from mapSlot: kept in MtlEntry::alphaMap (a cut-out's mask).
constexpr int kAlphaMapSlot = int(kTextureSlotCount);

// The glTF slot of a map statement (or kAlphaMapSlot), or -1 with the kind it is counted as in
// `unused`.
int mapSlot(std::string_view keyword, MtlUnused& unused) {
    ++unused.maps;
    if (keyword == "map_Kd") return int(TextureSlot::BaseColor);
    if (keyword == "map_d") return kAlphaMapSlot;
    if (keyword == "norm") return int(TextureSlot::Normal);
    if (keyword == "map_Ke") return int(TextureSlot::Emissive);
    if (keyword == "bump" || keyword == "map_Bump" || keyword == "map_bump")
        unused.add("bump (height) maps", "not rendered: only norm normal maps are read");
    else if (keyword == "map_Pr" || keyword == "map_Pm")
        unused.add("roughness and metallic maps (map_Pr, map_Pm)",
                   "glTF's one metallic-roughness image is not assembled from two files");
    else
        unused.add("texture maps without a glTF slot (map_Ka, map_Ks, map_Ns, disp, decal, refl, ...)",
                   "materials use their colours there");
    return -1;
}

}  // namespace

Status parseMtlFile(const std::string& path, const std::string& libraryName, MtlLibrary& library, MtlUnused& unused) {
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
            current->library = libraryName;
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
            if (const int slot = mapSlot(keyword, unused); slot >= 0) {
                MtlMap map;
                map.line = line;
                if (std::string problem = parseMap(p, eol, map, unused); !problem.empty())
                    return errorIn(name, "line " + std::to_string(line) + ": " + std::string(keyword) + ": " + problem);
                // A channel picks a scalar map's values; only map_d is read as one.
                if (map.channel != 0 && slot != kAlphaMapSlot)
                    unused.add("map options -imfchan (channel) on other maps than map_d", "the map is read without it");
                (slot == kAlphaMapSlot ? current->alphaMap : current->maps[size_t(slot)]) = std::move(map);
            }
        } else if (current && (keyword == "d" || keyword == "Tr")) {
            float value = 0.0f;  // opacity (d) or transparency (Tr = 1 - d); a malformed one is left alone
            if (parseField(p, eol, value) && std::isfinite(value))
                current->opacity = std::clamp(keyword == "d" ? value : 1.0f - value, 0.0f, 1.0f);
        } else if (current && (keyword == "Pr" || keyword == "Pm" || keyword == "Ps" || keyword == "Pc" ||
                               keyword == "Pcr" || keyword == "aniso" || keyword == "anisor")) {
            unused.add("PBR statements (Pr, Pm, Ps, Pc, Pcr, aniso)", "Kd, Ks and Ns decide the material");
        }
        p = eol + (eol < end ? 1 : 0);
    }
    return Status::ok();
}

}  // namespace vastray::import

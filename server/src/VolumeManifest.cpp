#include "VolumeManifest.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <set>
#include <stdexcept>

#include "ZipArchive.h"
#include "vastray/core/FilePath.h"
#include "vastray/core/VolumeLeaf.h"

namespace vastray::server {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// No manifest needs more: deeper documents are refused while they are parsed.
constexpr int kMaxManifestDepth = 8;

bool isVdb(const std::string& path) { return lowerExtension(path) == ".vdb"; }

// Why the manifest is refused; `what` names the element ("volumes[0].albedo").
class ManifestError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

[[noreturn]] void refuse(const std::string& what, const std::string& why) { throw ManifestError(what + " " + why); }

std::string typeName(const json& value) {
    return value.is_number() ? "a number" : value.is_string() ? "a string" : value.is_boolean() ? "a boolean"
           : value.is_array() ? "an array" : value.is_object() ? "an object" : "null";
}

float number(const json& value, const std::string& what) {
    if (!value.is_number()) refuse(what, "is " + typeName(value) + "; expected a number");
    return float(value.get<double>());  // out of float's range: inf, refused by the range check
}

// A number (grey) or an array of 3 numbers (R, G, B), as the CLI's R,G,B or one value.
std::array<float, 3> color(const json& value, const std::string& what) {
    if (value.is_number()) {
        const float grey = number(value, what);
        return {grey, grey, grey};
    }
    if (!value.is_array() || value.size() != 3)
        refuse(what, "is " + (value.is_array() ? "an array of " + std::to_string(value.size()) : typeName(value)) +
                         "; expected a number or an array of 3 numbers (R, G, B)");
    return {number(value[0], what + "[0]"), number(value[1], what + "[1]"), number(value[2], what + "[2]")};
}

std::string text(const json& value, const std::string& what) {
    if (!value.is_string()) refuse(what, "is " + typeName(value) + "; expected a string");
    return value.get<std::string>();
}

// volumes[i].file: a .vdb among the zip's files, by the same name rules as the zip's entries.
fs::path volumeFile(const json& value, const std::string& what, const std::set<std::string>& files) {
    const std::string file = text(value, what);
    const std::string quoted = "'" + file.substr(0, 200) + "'";
    if (const std::string why = unsafeZipEntryName(file, ZipLimits{}); !why.empty()) refuse(what + " " + quoted + ":", why);
    if (!isVdb(file)) refuse(what + " " + quoted + ":", "expected a .vdb file");
    if (!files.count(file)) refuse(what + " " + quoted + ":", "no such file in the zip");
    return fs::path(file);
}

VolumeSource volumeSource(const json& entry, const std::string& what, const fs::path& folder,
                          const std::set<std::string>& files, const std::string& label) {
    if (!entry.is_object()) refuse(what, "is " + typeName(entry) + "; expected an object");
    if (!entry.contains("file")) refuse(what, "has no \"file\" (the .vdb's path in the zip)");
    VolumeSource source;
    std::string temperatureGrid;
    for (const auto& [key, value] : entry.items()) {
        const std::string field = what + "." + key;
        if (key == "file") source.path = (folder / volumeFile(value, field, files)).string();
        else if (key == "grid") source.grid = text(value, field);
        else if (key == "albedo") source.material.albedo = color(value, field);
        else if (key == "density") source.material.densityScale = number(value, field);
        else if (key == "anisotropy") source.material.anisotropy = number(value, field);
        else if (key == "emission_grid") source.emissionGrid = text(value, field);
        else if (key == "temperature_grid") temperatureGrid = text(value, field);
        else if (key == "emission_scale") source.material.emission = color(value, field);
        else if (key == "codec") {
            const std::string name = text(value, field);
            const std::optional<VolumeCodec> codec = parseVolumeCodec(name);
            if (!codec) refuse(field, "'" + name.substr(0, 200) + "' is not a brick codec (expected float, fp16 or fp8)");
            source.codec = *codec;
        } else
            refuse(what, "has an unknown key '" + key.substr(0, 200) +
                             "' (expected file, grid, albedo, density, anisotropy, emission_grid, temperature_grid, "
                             "emission_scale, codec)");
    }
    if (!temperatureGrid.empty() && !source.emissionGrid.empty())
        refuse(what, "has both \"emission_grid\" and \"temperature_grid\"; give one of them");
    if (!temperatureGrid.empty()) source.emissionGrid = temperatureGrid, source.material.temperature = true;
    source.label = label + ":" + entry["file"].get<std::string>();
    const std::string prefix = label + ":" + kVolumeManifestName + ": " + what + ".";
    source.names = {prefix + "albedo", prefix + "density", prefix + "anisotropy", prefix + "emission_scale"};
    return source;
}

json parseManifest(const fs::path& path) {
    std::error_code error;
    const uint64_t size = fs::file_size(path, error);
    if (error) throw ManifestError("cannot be read: " + error.message());
    if (size > kMaxVolumeManifestBytes)
        throw ManifestError("is " + std::to_string(size) + " bytes, above the limit of " +
                            std::to_string(kMaxVolumeManifestBytes));
    std::ifstream in(path, std::ios::binary);
    std::string bytes(size, '\0');
    if (!in.read(bytes.data(), std::streamsize(size))) throw ManifestError("cannot be read");
    const json::parser_callback_t depthLimit = [](int depth, json::parse_event_t, json&) {
        if (depth > kMaxManifestDepth)
            throw ManifestError("is nested more than " + std::to_string(kMaxManifestDepth) + " levels deep");
        return true;
    };
    try {
        return json::parse(bytes, depthLimit);
    } catch (const json::parse_error& e) {
        const std::string what = e.what();  // "[json.exception.parse_error.101] parse error at ..."
        const size_t at = what.find("] ");
        throw ManifestError("is not JSON: " + (at == std::string::npos ? what : what.substr(at + 2)));
    }
}

}  // namespace

ServiceResult<ZipVolumes> readVolumeManifest(const fs::path& folder, const std::vector<fs::path>& files,
                                             const std::string& zipName) {
    std::set<std::string> names;
    for (const fs::path& f : files) names.insert(f.generic_string());
    ZipVolumes volumes;
    const std::string manifestName = zipName + ":" + kVolumeManifestName;
    std::set<std::string> listed;
    if (names.count(kVolumeManifestName)) {
        try {
            const json manifest = parseManifest(folder / kVolumeManifestName);
            if (!manifest.is_object()) refuse("the document", "is " + typeName(manifest) + "; expected an object");
            for (const auto& [key, value] : manifest.items())
                if (key != "volumes") refuse("the document", "has an unknown key '" + key.substr(0, 200) + "' (expected volumes)");
            if (!manifest.contains("volumes")) refuse("the document", "has no \"volumes\" (an array)");
            const json& list = manifest["volumes"];
            if (!list.is_array()) refuse("volumes", "is " + typeName(list) + "; expected an array");
            if (list.size() > kMaxVolumes)
                refuse("volumes", "lists " + std::to_string(list.size()) + " volumes, above the limit of " +
                                      std::to_string(kMaxVolumes));
            for (size_t i = 0; i < list.size(); ++i) {
                volumes.sources.push_back(volumeSource(list[i], "volumes[" + std::to_string(i) + "]", folder, names, zipName));
                listed.insert(list[i]["file"].get<std::string>());
            }
        } catch (const ManifestError& e) {
            return invalidArgument("data", manifestName + ": " + e.what());
        } catch (const std::exception& e) {  // nlohmann's other errors, allocation
            return invalidArgument("data", manifestName + ": cannot be read: " + e.what());
        }
    }
    for (const std::string& file : names)
        if (isVdb(file) && !listed.count(file))
            volumes.warnings.push_back(zipName + ":" + file + ": not imported: no volume of " + kVolumeManifestName +
                                       " at the zip's root names it");
    return volumes;
}

}  // namespace vastray::server

// Wavefront OBJ: v/vt/vn/f, negative indices, ear-clipped polygons, usemtl/mtllib.
// The whole file is read once and parsed in place with std::from_chars.
#include <cstring>
#include <filesystem>
#include <limits>
#include <unordered_map>

#include "import/ImportCommon.h"
#include "import/MtlLibrary.h"
#include "import/TextScan.h"
#include "import/Triangulate.h"
#include "vastray/streamer/Import.h"

namespace vastray {
namespace {

using import::parseNumber;

class ObjParser {
public:
    ObjParser(std::string path, ImportedMesh& out)
        : path_(std::move(path)), name_(import::fileNameOf(path_)), out_(out) {}

    Status parse(const char* p, const char* end) {
        for (line_ = 1; p < end; ++line_) {
            const char* eol = static_cast<const char*>(std::memchr(p, '\n', end - p));
            if (!eol) eol = end;
            if (Status s = parseLine(p, eol); !s.isOk()) return s;
            p = eol + (eol < end ? 1 : 0);
        }
        return applyMaterialLibraries();
    }

    const std::string& name() const { return name_; }
    uint64_t normalCount() const { return normalCount_; }
    uint64_t texcoordCount() const { return texcoordCount_; }

private:
    Status lineError(const std::string& message) const {
        return import::errorIn(name_, "line " + std::to_string(line_) + ": " + message);
    }

    Status parseLine(const char* p, const char* eol) {
        const std::string_view keyword = import::nextToken(p, eol);
        if (keyword == "v") return parseVertex(p, eol);
        if (keyword == "vt") return countAttribute(p, eol, 1, texcoordCount_, "vt");  // v and w optional
        if (keyword == "vn") return countAttribute(p, eol, 3, normalCount_, "vn");
        if (keyword == "f") return parseFace(p, eol);
        if (keyword == "usemtl") return useMaterial(std::string(import::trimmed(p, eol)));
        if (keyword == "mtllib") libraries_.emplace_back(import::trimmed(p, eol));
        return Status::ok();  // comments, o, g, s, l, p and unknown statements
    }

    Status parseVertex(const char* p, const char* eol) {
        Vec3f v;
        if (!import::parseField(p, eol, v.x) || !import::parseField(p, eol, v.y) || !import::parseField(p, eol, v.z))
            return lineError("malformed vertex position");
        if (out_.mesh.positions.size() >= std::numeric_limits<uint32_t>::max())
            return lineError("vertex count exceeds the uint32 index range");
        out_.mesh.positions.push_back(v);
        return Status::ok();
    }

    // vt/vn are not carried into the mesh, but a malformed one is still an error.
    Status countAttribute(const char* p, const char* eol, int required, uint64_t& count, const char* what) {
        for (int i = 0; i < required; ++i) {
            float value;
            if (!import::parseField(p, eol, value)) return lineError(std::string("malformed ") + what);
        }
        ++count;
        return Status::ok();
    }

    // OBJ indices are 1-based; negative ones count back from the last element defined so far.
    Status resolve(int64_t index, uint64_t defined, const char* what, uint32_t& out) const {
        const int64_t resolved = index > 0 ? index - 1 : static_cast<int64_t>(defined) + index;
        if (index == 0 || resolved < 0 || static_cast<uint64_t>(resolved) >= defined)
            return lineError(std::string(what) + " index " + std::to_string(index) +
                             " is out of range (" + std::to_string(defined) + " defined so far)");
        out = static_cast<uint32_t>(resolved);
        return Status::ok();
    }

    Status parseCorner(std::string_view token, uint32_t& vertex) const {
        const char* p = token.data();
        const char* end = p + token.size();
        int64_t index = 0;
        if (!parseNumber(p, end, index)) return lineError("malformed face corner '" + std::string(token) + "'");
        if (Status s = resolve(index, out_.mesh.positions.size(), "vertex", vertex); !s.isOk()) return s;
        const uint64_t counts[2] = {texcoordCount_, normalCount_};
        const char* names[2] = {"texcoord", "normal"};
        for (int slot = 0; slot < 2 && p < end; ++slot) {
            if (*p != '/') return lineError("malformed face corner '" + std::string(token) + "'");
            ++p;
            if (p < end && *p == '/') continue;  // v//vn: no texcoord
            uint32_t ignored;
            if (!parseNumber(p, end, index)) return lineError("malformed face corner '" + std::string(token) + "'");
            if (Status s = resolve(index, counts[slot], names[slot], ignored); !s.isOk()) return s;
        }
        if (p != end) return lineError("malformed face corner '" + std::string(token) + "'");
        return Status::ok();
    }

    Status parseFace(const char* p, const char* eol) {
        corners_.clear();
        for (std::string_view token = import::nextToken(p, eol); !token.empty();
             token = import::nextToken(p, eol)) {
            uint32_t vertex;
            if (Status s = parseCorner(token, vertex); !s.isOk()) return s;
            if (corners_.size() == import::kMaxPolygonCorners)
                return lineError("face has more than " + std::to_string(import::kMaxPolygonCorners) +
                                 " corners (the polygon limit)");
            corners_.push_back(vertex);
        }
        if (corners_.size() < 3)
            return lineError("face has " + std::to_string(corners_.size()) + " vertices (need at least 3)");
        const uint32_t material = currentMaterial();
        const uint64_t triangles = triangulator_.triangulate(out_.mesh.positions, corners_, out_.mesh.indices);
        if (!triangulator_.failure().empty()) return lineError("face: " + triangulator_.failure());
        out_.mesh.materialIds.insert(out_.mesh.materialIds.end(), triangles, material);
        return Status::ok();
    }

    // A bare "usemtl" selects the default material (some exporters write it).
    Status useMaterial(std::string name) {
        current_ = materialId(name);
        return Status::ok();
    }

    uint32_t materialId(const std::string& name) {
        auto [it, inserted] = materialIds_.try_emplace(name, static_cast<uint32_t>(out_.mesh.materials.size()));
        if (inserted) out_.mesh.materials.push_back(Material{name});
        return it->second;
    }

    // Faces before any usemtl share one default material, created on first use.
    uint32_t currentMaterial() {
        if (current_ < 0) current_ = materialId("");
        return static_cast<uint32_t>(current_);
    }

    Status applyMaterialLibraries();

    // "mtllib a.mtl b.mtl" names two files, but some exporters write one name with spaces.
    std::vector<std::string> libraryFiles() const {
        std::vector<std::string> files;
        for (const std::string& line : libraries_) {
            files.push_back(line);
            const char* p = line.data();
            const char* end = p + line.size();
            for (auto t = import::nextToken(p, end); !t.empty(); t = import::nextToken(p, end))
                if (t.size() != line.size()) files.emplace_back(t);
        }
        return files;
    }

    std::string path_;
    std::string name_;
    ImportedMesh& out_;
    uint64_t line_ = 0;
    uint64_t texcoordCount_ = 0;
    uint64_t normalCount_ = 0;
    int64_t current_ = -1;
    std::vector<uint32_t> corners_;  // reused for every face: no per-face allocation
    import::PolygonTriangulator triangulator_;
    std::unordered_map<std::string, uint32_t> materialIds_;
    std::vector<std::string> libraries_;

};

// A library next to the model is optional: exporters often reference one they never wrote.
// Like glTF URIs, names stay inside the model's folder: the service imports uploaded OBJ
// files, and a client must not make it read (and render the colours of) files elsewhere.
Status ObjParser::applyMaterialLibraries() {
    import::MtlLibrary library;
    const std::filesystem::path folder = import::directoryOf(path_);
    for (const std::string& name : libraryFiles()) {
        std::string why;
        if (!import::isSafeRelativeUri(name, why)) return import::errorIn(name_, "mtllib '" + name + "' " + why);
        const std::filesystem::path file = folder / name;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec)) continue;
        if (!import::insideFolder(folder, file))
            return import::errorIn(name_, "mtllib '" + name + "' resolves outside the model folder (a link)");
        if (Status s = import::parseMtlFile(file.string(), library); !s.isOk()) return s;
    }
    for (Material& m : out_.mesh.materials) {
        if (m.name.empty()) m.name = "default";
        const auto it = library.find(m.name);
        if (it == library.end()) continue;
        const import::MtlEntry& e = it->second;
        m.baseColor = {e.diffuse[0], e.diffuse[1], e.diffuse[2], 1.0f};
        m.emissive = e.emissive;
    }
    return Status::ok();
}

Result<ImportedMesh> importObjUnguarded(const std::string& path, const ImportOptions& options) {
    auto bytes = import::readWholeFile(path);
    if (!bytes) return bytes.status();
    ImportedMesh imported;
    imported.report.format = "obj";
    ObjParser parser(path, imported);
    const char* data = bytes->data();
    if (Status s = parser.parse(data, data + bytes->size()); !s.isOk()) return s;
    imported.report.verticesRead = imported.mesh.positions.size();
    imported.report.normalsRead = parser.normalCount();
    imported.report.texcoordsRead = parser.texcoordCount();
    if (Status s = finalizeMesh(parser.name(), options, imported); !s.isOk()) return s;
    return imported;
}

}  // namespace

Result<ImportedMesh> importObj(const std::string& path, const ImportOptions& options) {
    return import::guarded(path, [&]() -> Result<ImportedMesh> { return importObjUnguarded(path, options); });
}

}  // namespace vastray

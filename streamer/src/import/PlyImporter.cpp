// PLY (ASCII, binary little/big endian): vertex x/y/z of any scalar type, shading normals
// (nx/ny/nz) and colours (red/green/blue: integers scaled by their type's maximum, floats in
// [0, 1], both taken as sRGB-encoded), face polygons (ear-clipped, Triangulate.h), tristrips
// (-1 restarts), every other element skipped.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

#include "import/ImportCommon.h"
#include "import/PlyHeader.h"
#include "import/PlyReaders.h"
#include "import/Triangulate.h"
#include "vastray/core/VertexAttributes.h"
#include "vastray/streamer/Import.h"

namespace vastray {
namespace {

using import::PlyElement;
using import::PlyProperty;

// X..V are read in this order into a row's values (Role - X).
enum class Role : uint8_t { Skip, X, Y, Z, NX, NY, NZ, Red, Green, Blue, U, V };

Role roleOf(const PlyProperty& p) {
    if (p.isList) return Role::Skip;
    if (p.name == "x") return Role::X;
    if (p.name == "y") return Role::Y;
    if (p.name == "z") return Role::Z;
    if (p.name == "nx") return Role::NX;
    if (p.name == "ny") return Role::NY;
    if (p.name == "nz") return Role::NZ;
    if (p.name == "u" || p.name == "s" || p.name == "texture_u") return Role::U;
    if (p.name == "v" || p.name == "t" || p.name == "texture_v") return Role::V;
    if (p.name == "red" || p.name == "diffuse_red") return Role::Red;
    if (p.name == "green" || p.name == "diffuse_green") return Role::Green;
    if (p.name == "blue" || p.name == "diffuse_blue") return Role::Blue;
    return Role::Skip;
}

bool hasRoles(const std::vector<Role>& roles, std::initializer_list<Role> wanted) {
    for (Role r : wanted)
        if (std::find(roles.begin(), roles.end(), r) == roles.end()) return false;
    return true;
}

// A colour channel as [0, 1]: integers over their type's largest value, floats as they are.
double colourScale(import::PlyType type) {
    switch (type) {
        case import::PlyType::Int8: return 1.0 / 127.0;
        case import::PlyType::UInt8: return 1.0 / 255.0;
        case import::PlyType::Int16: return 1.0 / 32767.0;
        case import::PlyType::UInt16: return 1.0 / 65535.0;
        case import::PlyType::Int32: return 1.0 / 2147483647.0;
        case import::PlyType::UInt32: return 1.0 / 4294967295.0;
        default: return 1.0;
    }
}

uint8_t srgbByte(double c) { return uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); }

template <typename Reader>
class PlyBody {
public:
    // keepUvs: the header names a texture (PlyHeader::textureFiles); UVs are read and checked anyway.
    PlyBody(Reader reader, const std::string& name, ImportedMesh& out, bool keepUvs)
        : r_(reader), name_(name), out_(out), keepUvs_(keepUvs) {}

    Status element(const PlyElement& e) {
        if (e.name == "vertex") return vertices(e);
        if (e.name == "face") return polygons(e, false);
        if (e.name == "tristrips") return polygons(e, true);
        return skipElement(e);
    }

private:
    Status rowError(const PlyElement& e, uint64_t row, const std::string& what) const {
        return import::errorIn(name_, e.name + " " + std::to_string(row) + ": " + what);
    }

    bool skipList(const PlyProperty& p) {
        int64_t count;
        if (!r_.readInt(p.countType, count) || count < 0) return false;
        if (r_.canSkipRowsInBulk()) return r_.skipBytes(uint64_t(count) * import::plySize(p.type));
        for (int64_t i = 0; i < count; ++i)
            if (!r_.skip(p.type)) return false;
        return true;
    }

    bool skipProperty(const PlyProperty& p) { return p.isList ? skipList(p) : r_.skip(p.type); }

    Status skipElement(const PlyElement& e) {
        if (r_.canSkipRowsInBulk() && !e.hasLists()) {
            // count * row size cannot overflow: the header bounded count by the file size.
            if (!r_.skipBytes(e.count * e.minRowBytes(import::PlyFormat::BinaryLittleEndian)))
                return rowError(e, 0, "element extends past the end of the file");
            return Status::ok();
        }
        for (uint64_t row = 0; row < e.count; ++row)
            for (const PlyProperty& p : e.properties)
                if (!skipProperty(p)) return rowError(e, row, std::string(r_.failure()) + " in " + p.name);
        return Status::ok();
    }

    Status vertices(const PlyElement& e) {
        if (vertexCount_ != kNoVertices) return rowError(e, 0, "second vertex element");
        std::vector<Role> roles;
        for (const PlyProperty& p : e.properties) roles.push_back(roleOf(p));
        if (!hasRoles(roles, {Role::X, Role::Y, Role::Z}))
            return rowError(e, 0, "vertex element lacks an x, y or z property");
        // A normal or a colour is read only when all three of its properties are there, UVs when both are.
        const bool normals = hasRoles(roles, {Role::NX, Role::NY, Role::NZ});
        const bool colours = hasRoles(roles, {Role::Red, Role::Green, Role::Blue});
        const bool uvs = hasRoles(roles, {Role::U, Role::V});
        std::vector<double> scale(roles.size(), 1.0);
        for (size_t i = 0; i < roles.size(); ++i) {
            const bool used = (roles[i] >= Role::X && roles[i] <= Role::Z) ||
                              (normals && roles[i] >= Role::NX && roles[i] <= Role::NZ) ||
                              (colours && roles[i] >= Role::Red && roles[i] <= Role::Blue) ||
                              (uvs && (roles[i] == Role::U || roles[i] == Role::V));
            if (!used) roles[i] = Role::Skip;
            if (roles[i] >= Role::Red && roles[i] <= Role::Blue) scale[i] = colourScale(e.properties[i].type);
        }
        out_.mesh.positions.reserve(e.count);
        if (normals) out_.mesh.normals.reserve(e.count);
        if (colours) out_.mesh.colors.reserve(e.count);
        if (uvs && keepUvs_) out_.mesh.uvs.reserve(e.count);
        for (uint64_t row = 0; row < e.count; ++row) {
            double values[11] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
            for (size_t i = 0; i < roles.size(); ++i) {
                const PlyProperty& p = e.properties[i];
                const Role role = roles[i];
                const bool ok = role >= Role::X && role <= Role::V
                                    ? r_.readReal(p.type, values[int(role) - int(Role::X)])
                                    : skipProperty(p);
                if (!ok) return rowError(e, row, std::string(r_.failure()) + " in " + p.name);
                if (role >= Role::Red && role <= Role::Blue) values[int(role) - int(Role::X)] *= scale[i];
            }
            out_.mesh.positions.push_back(Vec3f{float(values[0]), float(values[1]), float(values[2])});
            if (normals)
                out_.mesh.normals.push_back(encodeOctahedral(Vec3f{float(values[3]), float(values[4]), float(values[5])}));
            if (colours)
                out_.mesh.colors.push_back(packSrgb8(srgbByte(values[6]), srgbByte(values[7]), srgbByte(values[8])));
            if (!uvs) continue;
            if (const std::string problem = import::uvProblem(values[9], values[10]); !problem.empty())
                return rowError(e, row, "texture coordinate " + problem);
            // v flipped: the package keeps glTF's texture space (docs/RENDERING.md).
            if (keepUvs_) out_.mesh.uvs.push_back({float(values[9]), 1.0f - float(values[10])});
        }
        vertexCount_ = e.count;
        if (normals) out_.report.normalsRead = e.count;
        if (colours) out_.report.coloursRead = e.count;
        if (uvs) out_.report.texcoordsRead = e.count;
        return Status::ok();
    }

    static const PlyProperty* indexList(const PlyElement& e) {
        for (const PlyProperty& p : e.properties)
            if (p.isList && (p.name == "vertex_indices" || p.name == "vertex_index")) return &p;
        return nullptr;
    }

    Status polygons(const PlyElement& e, bool strips) {
        const PlyProperty* list = indexList(e);
        if (!list) return rowError(e, 0, "no vertex_indices list property");
        if (vertexCount_ == kNoVertices && e.count > 0) return rowError(e, 0, "comes before the vertex element");
        if (!strips) out_.mesh.indices.reserve(out_.mesh.indices.size() + e.count * 3);
        for (uint64_t row = 0; row < e.count; ++row) {
            for (const PlyProperty& p : e.properties) {
                if (&p != list) {
                    if (!skipProperty(p)) return rowError(e, row, std::string(r_.failure()) + " in " + p.name);
                    continue;
                }
                if (Status s = readIndices(e, row, p, strips); !s.isOk()) return s;
                if (Status s = strips ? emitStrip(e, row) : emitPolygon(e, row); !s.isOk()) return s;
            }
        }
        return Status::ok();
    }

    Status readIndices(const PlyElement& e, uint64_t row, const PlyProperty& p, bool strips) {
        int64_t count;
        if (!r_.readInt(p.countType, count)) return rowError(e, row, std::string(r_.failure()) + " in list count");
        if (count < 0) return rowError(e, row, "negative list count " + std::to_string(count));
        if (!strips && uint64_t(count) > import::kMaxPolygonCorners)
            return rowError(e, row, "polygon has " + std::to_string(count) + " corners, more than the limit of " +
                                        std::to_string(import::kMaxPolygonCorners));
        corners_.clear();
        for (int64_t i = 0; i < count; ++i) {
            int64_t index;
            if (!r_.readInt(p.type, index)) return rowError(e, row, std::string(r_.failure()) + " in index list");
            const bool restart = strips && (index == -1 || (p.type == import::PlyType::UInt32 && index == 0xFFFFFFFFll));
            if (restart) {
                corners_.push_back(kRestart);
                continue;
            }
            if (index < 0)
                return rowError(e, row, "index " + std::to_string(index) + " is negative (vertex count " +
                                            std::to_string(vertexCount_) + ")");
            if (uint64_t(index) >= vertexCount_)
                return rowError(e, row, "index " + std::to_string(index) + " >= vertex count " +
                                            std::to_string(vertexCount_));
            corners_.push_back(uint32_t(index));
        }
        return Status::ok();
    }

    Status emitPolygon(const PlyElement& e, uint64_t row) {
        if (corners_.size() < 3)
            return rowError(e, row, "polygon with " + std::to_string(corners_.size()) + " vertices");
        triangulator_.triangulate(out_.mesh.positions, corners_, out_.mesh.indices);
        if (!triangulator_.failure().empty()) return rowError(e, row, triangulator_.failure());
        return Status::ok();
    }

    // Every second strip triangle is flipped so that all keep the strip's winding.
    Status emitStrip(const PlyElement&, uint64_t) {
        size_t run = 0;
        for (size_t i = 0; i < corners_.size(); ++i) {
            if (corners_[i] == kRestart) {
                run = 0;
                continue;
            }
            if (++run < 3) continue;
            const uint32_t a = corners_[i - 2], b = corners_[i - 1], c = corners_[i];
            if (run % 2 == 1) out_.mesh.indices.insert(out_.mesh.indices.end(), {a, b, c});
            else out_.mesh.indices.insert(out_.mesh.indices.end(), {b, a, c});
        }
        return Status::ok();
    }

    static constexpr uint64_t kNoVertices = std::numeric_limits<uint64_t>::max();
    static constexpr uint32_t kRestart = std::numeric_limits<uint32_t>::max();

    Reader r_;
    const std::string& name_;
    ImportedMesh& out_;
    const bool keepUvs_;
    uint64_t vertexCount_ = kNoVertices;
    std::vector<uint32_t> corners_;  // reused for every row: no per-face allocation
    import::PolygonTriangulator triangulator_;
};

template <typename Reader>
Status readBody(Reader reader, const import::PlyHeader& header, const std::string& name, ImportedMesh& out) {
    out.report.textureMaps = header.textureFiles;
    PlyBody<Reader> body(reader, name, out, header.textureFiles > 0);
    for (const PlyElement& e : header.elements)
        if (Status s = body.element(e); !s.isOk()) return s;
    return Status::ok();
}

const char* formatName(import::PlyFormat f) {
    switch (f) {
        case import::PlyFormat::Ascii: return "ply-ascii";
        case import::PlyFormat::BinaryLittleEndian: return "ply-binary-le";
        case import::PlyFormat::BinaryBigEndian: return "ply-binary-be";
    }
    return "ply";
}

Result<ImportedMesh> importPlyUnguarded(const std::string& path, const ImportOptions& options) {
    const std::string name = import::fileNameOf(path);
    auto bytes = import::readWholeFile(path);
    if (!bytes) return bytes.status();
    auto header = import::parsePlyHeader(bytes->data(), bytes->size(), name);
    if (!header) return header.status();
    ImportedMesh imported;
    imported.report.format = formatName(header->format);
    const char* body = bytes->data() + header->bodyOffset;
    const char* end = bytes->data() + bytes->size();
    const Status status = header->format == import::PlyFormat::Ascii
                              ? readBody(import::PlyAsciiReader(body, end), *header, name, imported)
                              : readBody(import::PlyBinaryReader(body, end, header->format == import::PlyFormat::BinaryBigEndian),
                                         *header, name, imported);
    if (!status.isOk()) return status;
    imported.report.verticesRead = imported.mesh.positions.size();
    if (Status s = finalizeMesh(name, options, imported); !s.isOk()) return s;
    return imported;
}

}  // namespace

Result<ImportedMesh> importPly(const std::string& path, const ImportOptions& options) {
    return import::guarded(path, [&]() -> Result<ImportedMesh> { return importPlyUnguarded(path, options); });
}

}  // namespace vastray

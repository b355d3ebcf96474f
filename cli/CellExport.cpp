#include "CellExport.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

namespace vastray::cli {
namespace {

// Corner k of a box: bit 0 picks x, bit 1 y, bit 2 z.
Vec3f corner(const Aabb& b, int k) { return {(k & 1 ? b.hi : b.lo).x, (k & 2 ? b.hi : b.lo).y, (k & 4 ? b.hi : b.lo).z}; }
constexpr int kFaces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};

void writeObj(std::ofstream& out, const std::vector<Cell>& cells) {
    out << "# vastray cells: one object per top-level cell\n";
    int empty = 0;
    for (size_t c = 0; c < cells.size(); ++c) {
        if (cells[c].chunk != kEmptyCell)
            out << "o chunk_" << cells[c].chunk << "\n";
        else
            out << "o empty_" << empty++ << "\n";
        for (int k = 0; k < 8; ++k) {
            const Vec3f p = corner(cells[c].box, k);
            out << "v " << p.x << ' ' << p.y << ' ' << p.z << "\n";
        }
        for (const auto& f : kFaces)
            out << "f " << 8 * c + f[0] + 1 << ' ' << 8 * c + f[1] + 1 << ' ' << 8 * c + f[2] + 1 << ' '
                << 8 * c + f[3] + 1 << "\n";
    }
}

void writePly(std::ofstream& out, const std::vector<Cell>& cells) {
    out << "ply\nformat ascii 1.0\ncomment vastray cells: chunk_id -1 marks an empty cell\n";
    out << "element vertex " << cells.size() * 8 << "\nproperty float x\nproperty float y\nproperty float z\n";
    out << "element face " << cells.size() * 6
        << "\nproperty list uchar int vertex_indices\nproperty int chunk_id\nend_header\n";
    for (const Cell& cell : cells)
        for (int k = 0; k < 8; ++k) {
            const Vec3f p = corner(cell.box, k);
            out << p.x << ' ' << p.y << ' ' << p.z << "\n";
        }
    for (size_t c = 0; c < cells.size(); ++c)
        for (const auto& f : kFaces)
            out << "4 " << 8 * c + f[0] << ' ' << 8 * c + f[1] << ' ' << 8 * c + f[2] << ' ' << 8 * c + f[3] << ' '
                << (cells[c].chunk == kEmptyCell ? int64_t(-1) : int64_t(cells[c].chunk)) << "\n";
}

}  // namespace

Status exportCells(const PackageInfo& info, const std::string& path) {
    const std::string extension = std::filesystem::path(path).extension().string();
    if (extension != ".obj" && extension != ".ply")
        return Status::error("--export-cells '" + path + "' must end in .obj or .ply");
    std::ofstream out(path);
    if (!out) return Status::error(path + ": cannot create");
    out.precision(9);
    const std::vector<Cell> cells = topLevelCells(info);
    if (extension == ".obj")
        writeObj(out, cells);
    else
        writePly(out, cells);
    out.close();
    if (!out) return Status::error(path + ": write failed");
    return Status::ok();
}

}  // namespace vastray::cli

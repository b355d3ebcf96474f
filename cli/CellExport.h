#pragma once
#include <string>

#include "vastray/core/Result.h"
#include "vastray/streamer/ScenePackage.h"

namespace vastray::cli {

// Every leaf cell of the top-level tree as a box (6 quads): .obj with one object per cell
// named chunk_<id> (or empty_<n>), or .ply with an int `chunk_id` per face (-1 = empty cell).
Status exportCells(const PackageInfo& info, const std::string& path);

}  // namespace vastray::cli

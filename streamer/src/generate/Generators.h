#pragma once
// One pair of functions per generator kind: exact counts (arithmetic only) and the stream.
// Options reaching these are already validated by Generate.cpp.
#include "vastray/streamer/Generate.h"

namespace vastray::gen {

GeneratedCounts sphereCounts(uint64_t triangles);
Status generateSphere(const GenerateOptions& options, MeshSink& sink);

GeneratedCounts terrainCounts(uint64_t triangles);
Status generateTerrain(const GenerateOptions& options, MeshSink& sink);

GeneratedCounts soupCounts(uint64_t triangles);
Status generateSoup(const GenerateOptions& options, MeshSink& sink);

GeneratedCounts cityCounts(uint64_t triangles);
Status generateCity(const GenerateOptions& options, MeshSink& sink);

}  // namespace vastray::gen

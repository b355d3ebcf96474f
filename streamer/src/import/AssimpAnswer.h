#pragma once
// The assimp child process's answer on its pipe (AssimpImporter.cpp): the imported mesh, its
// report and the opacity masks the parent bakes, or the child's error. The parent reads it
// back field by field and refuses anything out of range, so a child that misbehaves fails the
// import instead of handing the parent bad indices. Private to streamer/src/import; no assimp
// type here.
#include <cstdint>
#include <string>
#include <vector>

#include "import/AlphaMask.h"
#include "vastray/core/Result.h"
#include "vastray/streamer/Import.h"

namespace vastray::import {

// A byte (1: a mesh follows, 0: an error message follows), then the fields in a fixed order,
// strings and arrays each after their uint64 length (the package's ByteWriter).
std::vector<uint8_t> encodeAssimpAnswer(const Result<ImportedMesh>& result,
                                        const std::vector<AlphaMaskRequest>& masks = {});

// What encodeAssimpAnswer wrote; the child's error as it sent it, or a malformed answer as an
// error naming `name` (the model file).
Result<ImportedMesh> decodeAssimpAnswer(const std::string& name, const std::vector<uint8_t>& bytes,
                                        std::vector<AlphaMaskRequest>& masks);

}  // namespace vastray::import

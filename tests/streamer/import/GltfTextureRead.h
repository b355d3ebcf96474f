#pragma once
// The glTF texture tests' reader: a glTF written into the test folder, loaded and its textures
// read as the importer reads them.
#include <filesystem>
#include <string>

#include "ImportTestFiles.h"
#include "import/GltfLoader.h"
#include "import/GltfTextures.h"

namespace vastray::test {

inline Result<import::GltfTextures> readTextures(const std::string& name, const std::string& json,
                                                 ImportReport& report) {
    const std::string path = writeFile(name, json);
    auto model = import::loadGltfModel(path, false);
    if (!model) return model.status();
    return import::readGltfTextures(*model, name, std::filesystem::path(path).parent_path().string(), report);
}

}  // namespace vastray::test

#pragma once
// Type checks of a glTF 2.0 document against the parts of the schema the loader reads
// (glTF 2.0 spec, chapter 5): a wrongly typed field is reported with its JSON pointer
// ("/meshes/0/primitives: expected an array, found an object") instead of reaching
// tinygltf or nlohmann, whose messages named neither the field nor the path.
#include <nlohmann/json.hpp>

#include "vastray/core/Result.h"

namespace vastray::import {

Status checkGltfTypes(const nlohmann::json& doc);

}  // namespace vastray::import

#pragma once
// A glTF floor lit by KHR_lights_punctual lights, for the CLI and server light tests: the quad
// [-2, 2]^2 at y = 0 facing +y (node 0), the extension's `lights` (JSON array items) and the
// nodes that place them (JSON objects after node 0, each a root: the file has no scenes).
#include <string>

namespace vastray::test {

inline std::string litFloorGltf(const std::string& lights, const std::string& lightNodes) {
    return R"({"asset":{"version":"2.0"},
 "buffers":[{"byteLength":60,"uri":"data:application/octet-stream;base64,AAAAwAAAAAAAAADAAAAAQAAAAAAAAADAAAAAQAAAAAAAAABAAAAAwAAAAAAAAABAAAACAAEAAAADAAIA"}],
 "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":12}],
 "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":4,"min":[-2,0,-2],"max":[2,0,2]},
              {"bufferView":1,"componentType":5123,"type":"SCALAR","count":6}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
 "extensionsUsed":["KHR_lights_punctual"],
 "extensions":{"KHR_lights_punctual":{"lights":[)" +
           lights + R"(]}},
 "nodes":[{"mesh":0},)" + lightNodes + "]}";  // no scenes: every node is a root
}

}  // namespace vastray::test

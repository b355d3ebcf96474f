#pragma once
// A glTF of one triangle and two perspective cameras, "Near" at z = 3 and "Far" at (0.5, 0, 6),
// both looking down -z with yfov 0.8 rad: what the HTTP and gRPC scene-camera tests upload.

namespace vastray::test {

inline constexpr const char* kCamerasGltf = R"({"asset":{"version":"2.0"},
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AACAvwAAgL8AAAAAAACAPwAAgL8AAAAAAAAAAAAAgD8AAAAA"}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "accessors":[{"bufferView":0,"componentType":5126,"type":"VEC3","count":3,"min":[-1,-1,0],"max":[1,1,0]}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
 "cameras":[{"name":"Near","type":"perspective","perspective":{"yfov":0.8,"znear":0.1}},
            {"name":"Far","type":"perspective","perspective":{"yfov":0.8,"znear":0.1}}],
 "nodes":[{"mesh":0},{"camera":0,"translation":[0,0,3]},{"camera":1,"translation":[0.5,0,6]}],
 "scenes":[{"nodes":[0,1,2]}]})";

}  // namespace vastray::test

// tinygltf's implementation, compiled once, with Draco (see TinyGltf.h).
#define TINYGLTF_IMPLEMENTATION
#include "import/TinyGltf.h"

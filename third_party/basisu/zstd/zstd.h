// Not Basis Universal's file: basisu_transcoder.cpp includes "../zstd/zstd.h" (its own copy of
// Zstandard, not vendored here); this forwards it to the system's libzstd, which vastray already
// links for texture pages (third_party/basisu/README.md).
#include <zstd.h>

// What every wf_*.comp kernel includes first: the shared structs and the state accessors.
#ifndef VASTRAY_WAVEFRONT_PRELUDE_GLSL
#define VASTRAY_WAVEFRONT_PRELUDE_GLSL
#include "shared/TraceTypes.h"
#include "shared/StreamTypes.h"
#include "shared/WavefrontTypes.h"
#include "shared/TextureTypes.h"
#include "common/WavefrontState.glsl"

#define kInfinity uintBitsToFloat(0x7f800000u)

// Paths of the wave this dispatch works on.
uint wavePaths() { return pc.pixelCount * pc.sampleCount; }
#endif  // VASTRAY_WAVEFRONT_PRELUDE_GLSL

// The AOVs of the tile's pixel-centre rays (one per pixel, walked like a closest-hit stream):
// depth, facing unit normal, base colour, primitive, chunk and texture coordinates; miss values
// where nothing was hit (and UV (0, 0) where the scene has none). The base colour has the
// material's maps (at the level of the pixel's cone: core/RayCone.h), the normal its normal map; with paged textures a pixel whose map reads an
// absent page asks for it, writes
// nothing and joins kShadeWaitQueue; the host loads the pages and runs the kernel again over those
// pixels (pc.mode kAovRetry: the pixels of kShadeQueue).
#version 460
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_GOOGLE_include_directive : require

#include "common/WavefrontPrelude.glsl"
#include "common/Random.glsl"
#include "common/Shading.glsl"
#include "common/Attributes.glsl"
#include "common/Texture.glsl"
#include "common/MaterialMaps.glsl"

layout(local_size_x = kWavefrontWorkgroupSize) in;

// Same values as vastray::AovFlags.
const uint kAovDepth = 1u, kAovNormal = 2u, kAovAlbedo = 4u, kAovPrimId = 8u, kAovChunkId = 16u, kAovUv = 64u;

// Pixel i's AOVs; false when its base colour or normal waits for a texture page (nothing written).
bool writeAovs(ParamsRef params, uint i) {
    const uint aovs = params.p.aovs;
    const uvec4 n = UVec4Array(params.p.hitNormal).v[i];
    const bool found = (UVec2Array(params.p.rayState).v[i].x & kHitFound) != 0u;
    const vec4 position = Vec4Array(params.p.hitPosition).v[i];
    const uvec4 ids = UVec4Array(params.p.hitIds).v[i];
    vec3 normal = vec3(0.0), albedo = vec3(0.0);
    if (found) {
        // The shading normal and the base colour (times its map) times the vertex colour (white without).
        const vec3 facing = facingNormal(uintBitsToFloat(n.xyz), Vec4Array(params.p.rayDirection).v[i].xyz);
        normal = shadingNormalAt(n.w, facing);
        const WavefrontMaterial m = materialAt(params.p, ids.y);
        MaterialValues values = materialFactors(m);
        if ((aovs & (kAovAlbedo | kAovNormal)) != 0u && params.p.textures != 0ul && params.p.hitUv != 0ul &&
            hasMaps(m) &&
            !sampleMaterialMaps(params.p, m, hitUvOf(params.p, i),
                                hitFootprint(params.p, i, Vec4Array(params.p.rayDirection).v[i].xyz, facing,
                                             params.p.cameraSpread * position.w),
                                values))
            return false;
        if (values.normalMapped && params.p.hitFrame != 0ul)
            normal = bentNormal(params.p, i, n, facing, values.tangentNormal);
        albedo = values.baseColor * unpackHitColor(ids.w);
    }
    if ((aovs & kAovDepth) != 0u) RwFloatArray(params.p.outDepth).v[i] = found ? position.w : kInfinity;
    if ((aovs & kAovNormal) != 0u)
        for (uint c = 0u; c < 3u; ++c) RwFloatArray(params.p.outNormal).v[3u * i + c] = normal[c];
    if ((aovs & kAovAlbedo) != 0u)
        for (uint c = 0u; c < 3u; ++c) RwFloatArray(params.p.outAlbedo).v[3u * i + c] = albedo[c];
    if ((aovs & kAovPrimId) != 0u) RwUintArray(params.p.outPrimId).v[i] = found ? ids.x : 0xFFFFFFFFu;
    if ((aovs & kAovChunkId) != 0u) RwUintArray(params.p.outChunkId).v[i] = found ? ids.z : 0xFFFFFFFFu;
    if ((aovs & kAovUv) != 0u) {
        const bool uvs = found && params.p.hitUv != 0ul;
        RwFloatArray uvOut = RwFloatArray(params.p.outUv);
        uvOut.v[2u * i] = uvs ? RwFloatArray(params.p.hitUv).v[kHitUvFloats * i] : 0.0;
        uvOut.v[2u * i + 1u] = uvs ? RwFloatArray(params.p.hitUv).v[kHitUvFloats * i + 1u] : 0.0;
    }
    return true;
}

void main() {
    ParamsRef params = ParamsRef(pc.params);
    uint i = gl_GlobalInvocationID.x;
    bool live = i < pc.pixelCount;
    if (pc.mode == kAovRetry) {
        live = i < queueCount(params, kShadeQueue);
        if (live) i = queueOf(params, kShadeQueue).v[i];
    }
    const bool waits = live && !writeAovs(params, i);
    if (params.p.textureDemand != 0ul) appendToQueue(params, kShadeWaitQueue, false, waits ? 1u : 0u, i, 0u);
}

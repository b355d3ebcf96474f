// A material's maps at a hit: the GLSL twin of core/PathShading.h's sampleMaterial (the same
// steps: the UV transform, the finest level, glTF's channels), reading pages through the render's
// page table (common/Texture.glsl). Paged textures: a hit whose page is absent asks for it.
// Needs common/WavefrontPrelude.glsl, common/Attributes.glsl and common/Texture.glsl.
#ifndef VASTRAY_MATERIAL_MAPS_GLSL
#define VASTRAY_MATERIAL_MAPS_GLSL

#include "common/NormalMap.glsl"

// What the shading reads of a material at a hit: its factors times its maps, and the normal
// map's decoded texel (core/NormalMap.h decodeNormalTexel) when it has one.
struct MaterialValues {
    vec3 baseColor;
    float metallic;
    float roughness;
    vec3 emissive;
    bool normalMapped;
    vec3 tangentNormal;
};

MaterialValues materialFactors(WavefrontMaterial m) {
    return MaterialValues(vec3(m.baseR, m.baseG, m.baseB), m.metallic, m.roughness, vec3(m.emitR, m.emitG, m.emitB),
                          false, vec3(0.0, 0.0, 1.0));
}

bool hasMaps(WavefrontMaterial m) {
    return m.baseColorMap != kNoGpuTexture || m.metallicRoughnessMap != kNoGpuTexture ||
           m.emissiveMap != kNoGpuTexture || m.normalMap != kNoGpuTexture;
}

// Texture `texture` at uv mapped by t, level 0 (the reference's level: its pixel samples filter
// the texture); *entry: the page it reads; `absent` set when that page is not resident.
vec4 readMap(WavefrontParams p, uint texture, float t[6], vec2 uv, inout bool absent, out uint entry) {
    const GpuTexture g = GpuTextureArray(p.textures).v[texture];
    const vec2 at = mapUv(t, uv);
    entry = texturePageEntry(g, 0u, at);
    uint missing = kTexturePageAbsent;
    const vec4 value = sampleTexture(g, at, 0.0, TextureWords(p.texturePages), TextureWords(p.texturePool), missing);
    absent = absent || missing != kTexturePageAbsent;
    return value;
}

// v (the factors) times the material's maps at uv. false: a page it reads is absent (paged
// textures; v is then not to be used): every page it reads is asked for in textureDemand (the
// absent ones to be loaded, the resident ones to be kept while it waits: DeviceTextures::page).
bool sampleMaterialMaps(WavefrontParams p, WavefrontMaterial m, vec2 uv, inout MaterialValues v) {
    bool absent = false;
    uint base = kNoGpuTexture, metalRough = kNoGpuTexture, emissive = kNoGpuTexture, normal = kNoGpuTexture;
    if (m.baseColorMap != kNoGpuTexture) v.baseColor *= readMap(p, m.baseColorMap, m.baseColorUv, uv, absent, base).rgb;
    if (m.metallicRoughnessMap != kNoGpuTexture) {
        const vec4 t = readMap(p, m.metallicRoughnessMap, m.metallicRoughnessUv, uv, absent, metalRough);
        v.roughness *= t.g;
        v.metallic *= t.b;
    }
    if (m.emissiveMap != kNoGpuTexture) v.emissive *= readMap(p, m.emissiveMap, m.emissiveUv, uv, absent, emissive).rgb;
    if (m.normalMap != kNoGpuTexture) {
        const vec4 t = readMap(p, m.normalMap, m.normalUv, uv, absent, normal);
        precise float x = (2.0 * t.r - 1.0) * m.normalScale;
        precise float y = (2.0 * t.g - 1.0) * m.normalScale;
        precise float z = 2.0 * t.b - 1.0;
        v.normalMapped = true, v.tangentNormal = vec3(x, y, z);
    }
    if (!absent || p.textureDemand == 0ul) return !absent;
    RwUintArray demand = RwUintArray(p.textureDemand);
    if (base != kNoGpuTexture) atomicAdd(demand.v[base], 1u);
    if (metalRough != kNoGpuTexture) atomicAdd(demand.v[metalRough], 1u);
    if (emissive != kNoGpuTexture) atomicAdd(demand.v[emissive], 1u);
    if (normal != kNoGpuTexture) atomicAdd(demand.v[normal], 1u);
    return false;
}

// makeSurfacePoint's normal-mapped shading normal (docs/RENDERING.md, "Normal maps"): the front
// side's (interpolated, or geometric) normal bent by the map in the hit's frame, then turned to
// the ray's side (`facing`: the geometric normal on that side) when the unbent one is.
vec3 bentNormal(WavefrontParams p, uint j, uvec4 hitNormal, vec3 facing, vec3 local) {
    const vec3 front = normalize(uintBitsToFloat(hitNormal.xyz));
    const vec3 n = hitNormal.w != kNoNormal ? decodeOctahedral(hitNormal.w) : front;
    const bool turn = dot(n, facing) < 0.0;
    FloatArray frame = FloatArray(p.hitFrame);
    const vec3 dpdu = vec3(frame.v[6u * j], frame.v[6u * j + 1u], frame.v[6u * j + 2u]);
    const vec3 dpdv = vec3(frame.v[6u * j + 3u], frame.v[6u * j + 4u], frame.v[6u * j + 5u]);
    const vec3 bent = perturbNormal(n, dpdu, dpdv, local);
    return turn ? -bent : bent;
}

// The hit's texture coordinates (WavefrontParams::hitUv) of ray `ray`.
vec2 hitUvOf(WavefrontParams p, uint ray) {
    FloatArray uvs = FloatArray(p.hitUv);
    return vec2(uvs.v[2u * ray], uvs.v[2u * ray + 1u]);
}

#endif  // VASTRAY_MATERIAL_MAPS_GLSL

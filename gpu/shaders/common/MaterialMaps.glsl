// A material's maps at a hit: the GLSL twin of core/PathShading.h's sampleMaterial (the same
// steps: the UV transform, the ray cone's level, glTF's channels), reading pages through the render's
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
    float clearcoat, clearcoatRoughness;  // KHR_materials_clearcoat's factors times their maps
};

MaterialValues materialFactors(WavefrontMaterial m) {
    return MaterialValues(vec3(m.baseR, m.baseG, m.baseB), m.metallic, m.roughness, vec3(m.emitR, m.emitG, m.emitB),
                          false, vec3(0.0, 0.0, 1.0), m.clearcoat, m.clearcoatRoughness);
}

// The coat's maps are kNoGpuTexture where its factor is 0 (Wavefront.cpp setMaps).
bool hasMaps(WavefrontMaterial m) {
    return m.baseColorMap != kNoGpuTexture || m.metallicRoughnessMap != kNoGpuTexture ||
           m.emissiveMap != kNoGpuTexture || m.normalMap != kNoGpuTexture || m.clearcoatMap != kNoGpuTexture ||
           m.clearcoatRoughnessMap != kNoGpuTexture;
}

// A hit's footprint for the maps' levels (core/RayCone.h MapFootprint): the triangle's world
// area per unit of UV area (hitUv's third float), the ray cone's width at the hit and the cosine
// between the ray and the geometric normal. A zero footprint samples level 0.
struct MapFootprint {
    float worldPerUv;
    float coneWidth;
    float cosTheta;
};

// The pages a shading reads: two levels of each of the six maps at most.
const uint kMaxMapPages = 12u;

// Texture `texture` at uv mapped by t, at the level the footprint asks for (core/RayCone.h
// mapLod); with paged textures the page-table entries of the pages it reads are appended to
// pages[count] (in core no page is ever absent: nothing to ask for), and `absent` is set when one
// of them is not resident.
vec4 readMap(WavefrontParams p, uint texture, float t[6], vec2 uv, MapFootprint footprint, inout bool absent,
             inout uint pages[kMaxMapPages], inout uint count) {
    const GpuTexture g = GpuTextureArray(p.textures).v[texture];
    const vec2 at = mapUv(t, uv);
    const float texelArea = abs(t[0] * t[4] - t[1] * t[3]) * float(g.width) * float(g.height);
    const float lod = clampedLod(g, coneLod(texelArea, footprint.worldPerUv, footprint.coneWidth, footprint.cosTheta));
    const uint level = uint(lod);
    if (p.textureDemand != 0ul) {
        pages[count++] = texturePageEntry(g, level, at);
        if (lod > float(level)) pages[count++] = texturePageEntry(g, level + 1u, at);
    }
    uint missing = kTexturePageAbsent;
    const vec4 value = sampleTexture(g, at, lod, TextureWords(p.texturePages), TextureWords(p.texturePool), missing);
    absent = absent || missing != kTexturePageAbsent;
    return value;
}

// Paged textures, a read that found `absent` pages: asks for every page it read (pages[count]: the
// absent ones to be loaded, the resident ones to be kept while it waits, DeviceTextures::page)
// and returns false. true when nothing was absent.
bool asksForPages(WavefrontParams p, bool absent, uint pages[kMaxMapPages], uint count) {
    if (!absent || p.textureDemand == 0ul) return !absent;
    RwUintArray demand = RwUintArray(p.textureDemand);
    for (uint i = 0u; i < count; ++i) atomicAdd(demand.v[pages[i]], 1u);
    return false;
}

// v (the factors) times the material's maps at uv. false: a page it reads is absent (paged
// textures; v is then not to be used): every page it reads is asked for in textureDemand (the
// absent ones to be loaded, the resident ones to be kept while it waits: DeviceTextures::page).
bool sampleMaterialMaps(WavefrontParams p, WavefrontMaterial m, vec2 uv, MapFootprint footprint, inout MaterialValues v) {
    bool absent = false;
    uint pages[kMaxMapPages];
    uint count = 0u;
    if (m.baseColorMap != kNoGpuTexture)
        v.baseColor *= readMap(p, m.baseColorMap, m.baseColorUv, uv, footprint, absent, pages, count).rgb;
    if (m.metallicRoughnessMap != kNoGpuTexture) {
        const vec4 t = readMap(p, m.metallicRoughnessMap, m.metallicRoughnessUv, uv, footprint, absent, pages, count);
        v.roughness *= t.g;
        v.metallic *= t.b;
    }
    if (m.emissiveMap != kNoGpuTexture)
        v.emissive *= readMap(p, m.emissiveMap, m.emissiveUv, uv, footprint, absent, pages, count).rgb;
    if (m.clearcoatMap != kNoGpuTexture)
        v.clearcoat *= readMap(p, m.clearcoatMap, m.clearcoatUv, uv, footprint, absent, pages, count).r;
    if (m.clearcoatRoughnessMap != kNoGpuTexture)
        v.clearcoatRoughness *= readMap(p, m.clearcoatRoughnessMap, m.clearcoatRoughnessUv, uv, footprint, absent, pages,
                                        count).g;
    if (m.normalMap != kNoGpuTexture) {
        const vec4 t = readMap(p, m.normalMap, m.normalUv, uv, footprint, absent, pages, count);
        precise float x = (2.0 * t.r - 1.0) * m.normalScale;
        precise float y = (2.0 * t.g - 1.0) * m.normalScale;
        precise float z = 2.0 * t.b - 1.0;
        v.normalMapped = true, v.tangentNormal = vec3(x, y, z);
    }
    return asksForPages(p, absent, pages, count);
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
    return vec2(uvs.v[kHitUvFloats * ray], uvs.v[kHitUvFloats * ray + 1u]);
}

// core/RayCone.h's scatterSpread: maxSpread * min(1, 1 / (pi * pdf)), maxSpread for a pdf that is
// not a positive finite number.
float scatterSpread(float pdf, float maxSpread) {
    if (!(pdf > 0.0) || isinf(pdf)) return maxSpread;
    return maxSpread * min(1.0, 1.0 / (kPi * pdf));
}

// Path j's footprint at its closest hit (ray direction `direction`, unit; `normal` the unit
// geometric normal, either side) for a cone of width coneWidth there.
MapFootprint hitFootprint(WavefrontParams p, uint j, vec3 direction, vec3 normal, float coneWidth) {
    return MapFootprint(FloatArray(p.hitUv).v[kHitUvFloats * j + 2u], coneWidth, dot(direction, normal));
}

#endif  // VASTRAY_MATERIAL_MAPS_GLSL

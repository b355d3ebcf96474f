// A material's maps at a hit: the GLSL twin of core/PathShading.h's sampleMaterial (the same
// steps: the UV transform, the finest level, glTF's channels), reading pages through the render's
// page table (common/Texture.glsl). Paged textures: a hit whose page is absent asks for it.
// Needs common/WavefrontPrelude.glsl, common/Attributes.glsl and common/Texture.glsl.
#ifndef VASTRAY_MATERIAL_MAPS_GLSL
#define VASTRAY_MATERIAL_MAPS_GLSL

// What the shading reads of a material at a hit: its factors times its maps.
struct MaterialValues {
    vec3 baseColor;
    float metallic;
    float roughness;
    vec3 emissive;
};

MaterialValues materialFactors(WavefrontMaterial m) {
    return MaterialValues(vec3(m.baseR, m.baseG, m.baseB), m.metallic, m.roughness, vec3(m.emitR, m.emitG, m.emitB));
}

bool hasMaps(WavefrontMaterial m) {
    return m.baseColorMap != kNoGpuTexture || m.metallicRoughnessMap != kNoGpuTexture || m.emissiveMap != kNoGpuTexture;
}

// applyUvTransform (core/MaterialTextures.h): each product and sum rounded on its own, as the host's.
vec2 mapUv(float t[6], vec2 uv) {
    precise float u = t[0] * uv.x + t[1] * uv.y;
    precise float v = t[3] * uv.x + t[4] * uv.y;
    precise float tu = u + t[2];
    precise float tv = v + t[5];
    return vec2(tu, tv);
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
    uint base = kNoGpuTexture, metalRough = kNoGpuTexture, emissive = kNoGpuTexture;
    if (m.baseColorMap != kNoGpuTexture) v.baseColor *= readMap(p, m.baseColorMap, m.baseColorUv, uv, absent, base).rgb;
    if (m.metallicRoughnessMap != kNoGpuTexture) {
        const vec4 t = readMap(p, m.metallicRoughnessMap, m.metallicRoughnessUv, uv, absent, metalRough);
        v.roughness *= t.g;
        v.metallic *= t.b;
    }
    if (m.emissiveMap != kNoGpuTexture) v.emissive *= readMap(p, m.emissiveMap, m.emissiveUv, uv, absent, emissive).rgb;
    if (!absent || p.textureDemand == 0ul) return !absent;
    RwUintArray demand = RwUintArray(p.textureDemand);
    if (base != kNoGpuTexture) atomicAdd(demand.v[base], 1u);
    if (metalRough != kNoGpuTexture) atomicAdd(demand.v[metalRough], 1u);
    if (emissive != kNoGpuTexture) atomicAdd(demand.v[emissive], 1u);
    return false;
}

// The hit's texture coordinates (WavefrontParams::hitUv) of ray `ray`.
vec2 hitUvOf(WavefrontParams p, uint ray) {
    FloatArray uvs = FloatArray(p.hitUv);
    return vec2(uvs.v[2u * ray], uvs.v[2u * ray + 1u]);
}

#endif  // VASTRAY_MATERIAL_MAPS_GLSL

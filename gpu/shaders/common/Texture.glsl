// Texture sampling: the GLSL twin of core/Texture.h's textureFootprint and sampleTexture
// (docs/RENDERING.md, "Textures"). Pages come from a pool of kGpuTexturePageWords-word slots
// through a page table; a page the table marks absent is reported, not guessed: the sample is
// then zero and `missing` names the page-table entry the caller must have loaded.
// Needs shared/TextureTypes.h, GL_EXT_buffer_reference and common/Attributes.glsl (srgbToLinear).
#ifndef VASTRAY_TEXTURE_GLSL
#define VASTRAY_TEXTURE_GLSL

layout(buffer_reference, std430, buffer_reference_align = 4) readonly buffer TextureWords { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer GpuTextureArray { GpuTexture v[]; };

// u mapped by the wrap mode, then the footprint's upper-left texel and the weight of the next.
void textureAxis(float u, uint size, uint wrap, out uint texel, out float weight) {
    if (isnan(u) || isinf(u)) u = 0.0;
    const float n = float(size);
    if (wrap == 0u) {  // repeat
        const float x = (u - floor(u)) * n - 0.5;
        const float x0 = floor(x);
        weight = x - x0;
        texel = x0 < 0.0 ? size - 1u : min(uint(x0), size - 1u);
        return;
    }
    if (wrap == 2u) {  // mirror
        const float t = u - 2.0 * floor(0.5 * u);
        u = t > 1.0 ? 2.0 - t : t;
    }
    const float x = clamp(clamp(u, 0.0, 1.0) * n - 0.5, 0.0, n - 1.0);
    texel = min(uint(floor(x)), size - 1u);
    weight = x - float(texel);
}

vec4 unpackTexel(uint word, bool linear) {
    const vec4 c = vec4(float(word & 0xFFu), float((word >> 8) & 0xFFu), float((word >> 16) & 0xFFu),
                        float(word >> 24)) / 255.0;
    return linear ? c : vec4(srgbToLinear(c.r), srgbToLinear(c.g), srgbToLinear(c.b), c.a);
}

// Where level `level`'s bilinear footprint at uv lies: its page's page-table entry (the return
// value), the footprint's upper-left texel in that level and the weights of the next texels.
uint textureFootprint(GpuTexture t, uint level, vec2 uv, out uint x, out uint y, out float fx, out float fy) {
    const uint w = max(1u, t.width >> level), h = max(1u, t.height >> level);
    textureAxis(uv.x, w, t.flags & 3u, x, fx);
    textureAxis(uv.y, h, (t.flags >> 2) & 3u, y, fy);
    const uint pagesX = (w + kGpuTexturePageTexels - 1u) / kGpuTexturePageTexels;
    return t.pageTable + t.levelFirstPage[level] + (y / kGpuTexturePageTexels) * pagesX + x / kGpuTexturePageTexels;
}

// The page-table entry of the page that level `level`'s bilinear footprint at uv reads.
uint texturePageEntry(GpuTexture t, uint level, vec2 uv) {
    uint x, y;
    float fx, fy;
    return textureFootprint(t, level, uv, x, y, fx, fy);
}

vec4 bilinearTexture(GpuTexture t, uint level, vec2 uv, TextureWords pageTable, TextureWords pool, inout uint missing) {
    uint x, y;
    float fx, fy;
    const uint entry = textureFootprint(t, level, uv, x, y, fx, fy);
    const uint slot = pageTable.v[entry];
    if (slot == kTexturePageAbsent) {
        missing = entry;
        return vec4(0.0);
    }
    const uint base = slot * kGpuTexturePageWords + (y % kGpuTexturePageTexels) * kGpuTexturePageSide +
                      x % kGpuTexturePageTexels;
    const bool linear = (t.flags & kTextureFlagLinear) != 0u;
    const vec4 a = unpackTexel(pool.v[base], linear), b = unpackTexel(pool.v[base + 1u], linear);
    const vec4 c = unpackTexel(pool.v[base + kGpuTexturePageSide], linear);
    const vec4 d = unpackTexel(pool.v[base + kGpuTexturePageSide + 1u], linear);
    return (1.0 - fx) * (1.0 - fy) * a + fx * (1.0 - fy) * b + (1.0 - fx) * fy * c + fx * fy * d;
}

// core/Texture.h's textureLod: 0.5 log2(texelArea / worldArea) + log2(coneWidth / |cos|), 0 for
// degenerate inputs.
float coneLod(float texelArea, float worldArea, float coneWidth, float cosTheta) {
    const float c = abs(cosTheta);
    if (!(texelArea > 0.0) || !(worldArea > 0.0) || !(coneWidth > 0.0) || !(c > 1e-6)) return 0.0;
    const float lod = 0.5 * log2(texelArea / worldArea) + log2(coneWidth / c);
    return (isnan(lod) || isinf(lod)) ? 0.0 : lod;
}

// lod clamped to the texture's levels (a non-finite one: 0), as sampleTexture clamps it.
float clampedLod(GpuTexture t, float lod) {
    return (isnan(lod) || isinf(lod)) ? 0.0 : clamp(lod, 0.0, float(t.levelCount - 1u));
}

// Trilinear at level of detail `lod` (clamped to the texture's levels). `missing` is left as it
// was when every page was there.
vec4 sampleTexture(GpuTexture t, vec2 uv, float lod, TextureWords pageTable, TextureWords pool, inout uint missing) {
    lod = clampedLod(t, lod);
    const uint l0 = uint(lod);
    const float f = lod - float(l0);
    const vec4 a = bilinearTexture(t, l0, uv, pageTable, pool, missing);
    if (f <= 0.0 || l0 + 1u >= t.levelCount) return a;
    const vec4 b = bilinearTexture(t, l0 + 1u, uv, pageTable, pool, missing);
    return a + f * (b - a);
}

#endif  // VASTRAY_TEXTURE_GLSL

// The metallic-roughness BSDF (core/Microfacet.h, core/src/Microfacet.cpp) in GLSL, step for
// step: GGX with height-correlated Smith masking and Schlick's Fresnel, the multiple-scattering
// scale 1 + F0 (1 / E - 1), the dielectric's diffuse base weighted by what its layer leaves,
// visible-normal sampling. The albedo tables are the host's (WavefrontParams::microfacet).
// Directions are local (+z: the shading normal), wo towards the viewer.
#ifndef VASTRAY_MICROFACET_GLSL
#define VASTRAY_MICROFACET_GLSL

const float kDielectricF0 = 0.04;
const float kMinMicrofacetAlpha = 1e-3;
const uint kMicrofacetDielectricTable = kMicrofacetSide * kMicrofacetSide;
const uint kMicrofacetAverageTable = 2u * kMicrofacetSide * kMicrofacetSide;

// A surface point as next-event estimation and the bounce see it: geometric and shading normal
// (on the ray's side), base colour, the direction back along the ray; glossy: the
// metallic-roughness BSDF, else the Lambertian base alone.
struct Surface {
    vec3 n, ns, base, wo;
    bool glossy;
    float metallic, roughness, specular;
};

float microfacetAlpha(float roughness) { return max(roughness * roughness, kMinMicrofacetAlpha); }

float smithLambda(vec3 w, float alpha) {
    const float z = max(w.z, 1e-6);
    const float tan2 = (w.x * w.x + w.y * w.y) / (z * z);
    return 0.5 * (sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

float ggxD(vec3 h, float alpha) {
    const float a2 = alpha * alpha;
    const float t = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
    return a2 / (kPi * t * t);
}

float schlickWeight(float cosine) {
    const float c = 1.0 - clamp(cosine, 0.0, 1.0);
    const float c2 = c * c;
    return c2 * c2 * c;
}

vec3 sampleVisibleNormal(vec3 wo, float alpha, float u1, float u2) {
    const vec3 stretched = normalize(vec3(wo.x * alpha, wo.y * alpha, wo.z));
    const float phi = 2.0 * kPi * u1;
    const float z = (1.0 - u2) * (1.0 + stretched.z) - stretched.z;
    const float sinTheta = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    const vec3 h = vec3(sinTheta * cos(phi), sinTheta * sin(phi), z) + stretched;
    return normalize(vec3(h.x * alpha, h.y * alpha, max(h.z, 0.0)));
}

float microfacetTable(WavefrontParams p, uint table, float mu, float roughness) {
    const float last = float(kMicrofacetSide - 1u);
    const float x = clamp(mu, 0.0, 1.0) * last, y = clamp(roughness, 0.0, 1.0) * last;
    const uint x0 = min(uint(x), kMicrofacetSide - 2u), y0 = min(uint(y), kMicrofacetSide - 2u);
    const float fx = x - float(x0), fy = y - float(y0);
    const uint i = table + y0 * kMicrofacetSide + x0;
    FloatArray t = FloatArray(p.microfacet);
    const float low = t.v[i] + (t.v[i + 1u] - t.v[i]) * fx;
    const float high = t.v[i + kMicrofacetSide] + (t.v[i + kMicrofacetSide + 1u] - t.v[i + kMicrofacetSide]) * fx;
    return low + (high - low) * fy;
}

float microfacetAverage(WavefrontParams p, float roughness) {
    const float y = clamp(roughness, 0.0, 1.0) * float(kMicrofacetSide - 1u);
    const uint y0 = min(uint(y), kMicrofacetSide - 2u);
    FloatArray t = FloatArray(p.microfacet);
    const uint i = kMicrofacetAverageTable + y0;
    return t.v[i] + (t.v[i + 1u] - t.v[i]) * (y - float(y0));
}

// lobeAt: D G2 / (4 mu_o mu_i), cos(wo, h) and the visible-normal density, in x, y, z.
vec3 microfacetLobe(vec3 wo, vec3 wi, float alpha) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    const vec3 h = normalize(wo + wi);
    const float d = ggxD(h, alpha);
    const float lambdaO = smithLambda(wo, alpha), lambdaI = smithLambda(wi, alpha);
    return vec3(d / (4.0 * wo.z * wi.z * (1.0 + lambdaO + lambdaI)), dot(wo, h), d / (4.0 * wo.z * (1.0 + lambdaO)));
}

float specularPick(Surface s, float dielectricAlbedo) {
    const float base = (s.base.x + s.base.y + s.base.z) / 3.0;
    const float spec = (1.0 - s.metallic) * s.specular * dielectricAlbedo + s.metallic * base;
    const float diffuse = (1.0 - s.metallic) * base * (1.0 - s.specular * dielectricAlbedo);
    return spec + diffuse > 0.0 ? spec / (spec + diffuse) : 0.5;
}

vec3 evalBsdf(WavefrontParams p, Surface s, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return vec3(0.0);
    const vec3 lobe = microfacetLobe(wo, wi, microfacetAlpha(s.roughness));
    const float e = microfacetTable(p, 0u, wo.z, s.roughness);
    const float fresnel = schlickWeight(lobe.y);
    const vec3 f0 = s.base;
    const vec3 metal = (f0 + (vec3(1.0) - f0) * fresnel) * lobe.x * (vec3(1.0) + f0 * (1.0 / e - 1.0));
    const float layer = s.specular * (kDielectricF0 + (1.0 - kDielectricF0) * fresnel) * lobe.x *
                        (1.0 + kDielectricF0 * (1.0 / e - 1.0));
    const float left = (1.0 - s.specular * microfacetTable(p, kMicrofacetDielectricTable, wo.z, s.roughness)) *
                       (1.0 - s.specular * microfacetTable(p, kMicrofacetDielectricTable, wi.z, s.roughness)) /
                       (kPi * (1.0 - s.specular * microfacetAverage(p, s.roughness)));
    return (vec3(layer) + s.base * left) * (1.0 - s.metallic) + metal * s.metallic;
}

float bsdfPdf(WavefrontParams p, Surface s, vec3 wo, vec3 wi) {
    if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
    const float pick = specularPick(s, microfacetTable(p, kMicrofacetDielectricTable, wo.z, s.roughness));
    return pick * microfacetLobe(wo, wi, microfacetAlpha(s.roughness)).z + (1.0 - pick) * wi.z / kPi;
}

vec3 localOutgoing(vec3 tangent, vec3 bitangent, vec3 n, vec3 wo) {
    vec3 local = vec3(dot(tangent, wo), dot(bitangent, wo), dot(n, wo));
    if (local.z < 1e-4) local = normalize(vec3(local.x, local.y, 1e-4));
    return local;
}

// glossyReflection (core/src/PathShading.cpp): f cos towards wi and the bounce's density of wi.
vec3 glossyReflection(WavefrontParams p, Surface s, vec3 wi, out float pdf) {
    pdf = 0.0;
    if (dot(s.ns, wi) <= 0.0 || dot(s.n, wi) <= 0.0) return vec3(0.0);
    vec3 tangent, bitangent;
    frameAround(s.ns, tangent, bitangent);
    const vec3 wo = localOutgoing(tangent, bitangent, s.ns, s.wo);
    const vec3 local = vec3(dot(tangent, wi), dot(bitangent, wi), dot(s.ns, wi));
    pdf = bsdfPdf(p, s, wo, local);
    return evalBsdf(p, s, wo, local) * local.z;
}

// scatterSurface: the bounce's direction, f cos / pdf in weight and the density; false: none.
bool scatterSurface(WavefrontParams p, Surface s, uint pixel, uint sampleIndex, uint bounce, out vec3 direction,
                    out vec3 weight, out float pdf) {
    weight = vec3(0.0), direction = vec3(0.0), pdf = 0.0;
    vec3 tangent, bitangent;
    frameAround(s.ns, tangent, bitangent);
    const vec3 wo = localOutgoing(tangent, bitangent, s.ns, s.wo);
    const float u1 = randomFloat(pixel, sampleIndex, bounce, kDimDirectionU, p.seed);
    const float u2 = randomFloat(pixel, sampleIndex, bounce, kDimDirectionV, p.seed);
    const float pick = specularPick(s, microfacetTable(p, kMicrofacetDielectricTable, wo.z, s.roughness));
    vec3 wi;
    if (randomFloat(pixel, sampleIndex, bounce, kDimLobe, p.seed) < pick) {
        const vec3 h = sampleVisibleNormal(wo, microfacetAlpha(s.roughness), u1, u2);
        wi = normalize(h * (2.0 * dot(wo, h)) - wo);
    } else {
        const float r = sqrt(u1);
        const float phi = 2.0 * kPi * u2;
        wi = vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u1)));
    }
    if (wi.z <= 0.0) return false;
    pdf = bsdfPdf(p, s, wo, wi);
    if (!(pdf > 0.0)) return false;
    weight = evalBsdf(p, s, wo, wi) * (wi.z / pdf);
    if (any(isinf(weight)) || any(isnan(weight))) return false;
    direction = normalize(tangent * wi.x + bitangent * wi.y + s.ns * wi.z);
    return dot(direction, s.n) > 0.0;
}

#endif  // VASTRAY_MICROFACET_GLSL

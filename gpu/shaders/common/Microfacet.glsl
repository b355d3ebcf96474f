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
const uint kMicrofacetFresnelAverageTable = kMicrofacetAverageTable + kMicrofacetSide;
const uint kMicrofacetMixAverageTable = kMicrofacetFresnelAverageTable + kMicrofacetSide;

// A surface point as next-event estimation and the bounce see it: geometric and shading normal
// (on the ray's side), base colour, the direction back along the ray; glossy: the
// metallic-roughness BSDF, else the Lambertian base alone.
struct Surface {
    vec3 n, ns, base, wo;
    bool glossy;
    float metallic, roughness, specular;
    vec3 specularColor;  // the layer's F0 is min(dielectricF0 this, 1)
    float clearcoat, clearcoatRoughness;  // the coat over it all (0: none)
    float dielectricF0;                   // core iorF0 of the material's ior (the coat's is kDielectricF0)
    vec3 nc;  // the coat's normal (core SurfacePoint::coatNormal): ns before a normal map bent it
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

float microfacetAverage(WavefrontParams p, uint table, float roughness) {
    const float y = clamp(roughness, 0.0, 1.0) * float(kMicrofacetSide - 1u);
    const uint y0 = min(uint(y), kMicrofacetSide - 2u);
    FloatArray t = FloatArray(p.microfacet);
    const uint i = table + y0;
    return t.v[i] + (t.v[i + 1u] - t.v[i]) * (y - float(y0));
}

// lobeAt: D G2 / (4 mu_o mu_i), cos(wo, h) and the visible-normal density, in x, y, z (wo.z and
// wi.z > 0).
vec3 microfacetLobe(vec3 wo, vec3 wi, float alpha) {
    const vec3 h = normalize(wo + wi);
    const float d = ggxD(h, alpha);
    const float lambdaO = smithLambda(wo, alpha), lambdaI = smithLambda(wi, alpha);
    return vec3(d / (4.0 * wo.z * wi.z * (1.0 + lambdaO + lambdaI)), dot(wo, h), d / (4.0 * wo.z * (1.0 + lambdaO)));
}

// fresnelWeightAlbedo: W from E and Ed(0.04) at one (mu, r).
float fresnelWeightAlbedo(float e, float ed) {
    return (ed / (1.0 + kDielectricF0 * (1.0 / e - 1.0)) - kDielectricF0 * e) / (1.0 - kDielectricF0);
}

// layerAlbedo: the compensated layer's albedo per channel for normal-incidence reflectance f0.
vec3 layerAlbedo(vec3 f0, float e, float w) { return (f0 * e + (vec3(1.0) - f0) * w) * (vec3(1.0) + f0 * (1.0 / e - 1.0)); }

// outgoingTerms: alpha, E(mu_o), the layer's F0, albedo at mu_o and average per channel, and the
// specular lobe's pick, looked up once per event.
// The coat's frame (core CoatFrame): coatTilted false when the coat normal is +z, and then every
// direction is its own in it; coatWo: wo in it, lifted to a grazing 1e-4 below the coat.
struct BsdfOutgoing {
    float alpha, metalAlbedo, pick;
    vec3 f0, layerAlbedo, layerAverage;
    float coatAlpha, coatMetalAlbedo, coatAlbedo, coatPick;
    bool coatTilted;
    vec3 coatT, coatB, coatN, coatWo;
};
vec3 coatIn(BsdfOutgoing o, vec3 v) { return o.coatTilted ? vec3(dot(o.coatT, v), dot(o.coatB, v), dot(o.coatN, v)) : v; }
vec3 coatOut(BsdfOutgoing o, vec3 v) { return o.coatTilted ? o.coatT * v.x + o.coatB * v.y + o.coatN * v.z : v; }
// The coat normal in the shading frame (core bsdfOf): exactly +z unless it differs from ns.
vec3 localCoatNormal(Surface s, vec3 tangent, vec3 bitangent) {
    if (!(s.clearcoat > 0.0) || s.nc == s.ns) return vec3(0.0, 0.0, 1.0);
    return normalize(vec3(dot(tangent, s.nc), dot(bitangent, s.nc), dot(s.ns, s.nc)));
}
BsdfOutgoing outgoingTerms(WavefrontParams p, Surface s, vec3 wo, vec3 coatNormal) {
    BsdfOutgoing o;
    o.coatTilted = false, o.coatT = vec3(1.0, 0.0, 0.0), o.coatB = vec3(0.0, 1.0, 0.0), o.coatN = vec3(0.0, 0.0, 1.0);
    o.coatWo = wo;
    o.alpha = microfacetAlpha(s.roughness);
    o.metalAlbedo = microfacetTable(p, 0u, wo.z, s.roughness);
    const float w = fresnelWeightAlbedo(o.metalAlbedo, microfacetTable(p, kMicrofacetDielectricTable, wo.z, s.roughness));
    const float wAverage = microfacetAverage(p, kMicrofacetFresnelAverageTable, s.roughness);
    const float mixAverage = microfacetAverage(p, kMicrofacetMixAverageTable, s.roughness);
    o.f0 = min(s.dielectricF0 * s.specularColor, vec3(1.0));
    o.layerAlbedo = layerAlbedo(o.f0, o.metalAlbedo, w);
    o.layerAverage = o.f0 * o.f0 + (vec3(1.0) - o.f0) * (vec3(1.0) - o.f0) * wAverage + o.f0 * (vec3(1.0) - o.f0) * mixAverage;
    const float base = (s.base.x + s.base.y + s.base.z) / 3.0;
    const float layer = (o.layerAlbedo.x + o.layerAlbedo.y + o.layerAlbedo.z) / 3.0;
    const vec3 leftShare = s.base * (vec3(1.0) - s.specular * o.layerAlbedo) / 3.0;
    const float spec = (1.0 - s.metallic) * s.specular * layer + s.metallic * base;
    const float diffuse = (1.0 - s.metallic) * (leftShare.x + leftShare.y + leftShare.z);
    o.pick = spec + diffuse > 0.0 ? spec / (spec + diffuse) : 0.5;
    o.coatAlpha = 0.0, o.coatMetalAlbedo = 1.0, o.coatAlbedo = 0.0, o.coatPick = 0.0;
    if (s.clearcoat > 0.0) {
        o.coatTilted = coatNormal != vec3(0.0, 0.0, 1.0);
        if (o.coatTilted) {
            frameAround(coatNormal, o.coatT, o.coatB);
            o.coatN = coatNormal;
            o.coatWo = coatIn(o, wo);
            if (o.coatWo.z < 1e-4) o.coatWo = normalize(vec3(o.coatWo.x, o.coatWo.y, 1e-4));
        }
        o.coatAlpha = microfacetAlpha(s.clearcoatRoughness);
        o.coatMetalAlbedo = microfacetTable(p, 0u, o.coatWo.z, s.clearcoatRoughness);
        o.coatAlbedo = microfacetTable(p, kMicrofacetDielectricTable, o.coatWo.z, s.clearcoatRoughness);
        const float coat = s.clearcoat * o.coatAlbedo, under = (1.0 - coat) * (spec + diffuse);
        o.coatPick = coat + under > 0.0 ? coat / (coat + under) : 1.0;
    }
    return o;
}

// evalWith: f and the mixture's density from one lobe evaluation; wo.z > 0.
struct BsdfValue {
    vec3 f;
    float pdf;
};
BsdfValue evalBase(WavefrontParams p, Surface s, BsdfOutgoing o, vec3 wo, vec3 wi) {
    if (wi.z <= 0.0) return BsdfValue(vec3(0.0), 0.0);
    const vec3 lobe = microfacetLobe(wo, wi, o.alpha);
    const float fresnel = schlickWeight(lobe.y);
    const float lost = 1.0 / o.metalAlbedo - 1.0;
    const float eIn = microfacetTable(p, 0u, wi.z, s.roughness);
    const float wIn = fresnelWeightAlbedo(eIn, microfacetTable(p, kMicrofacetDielectricTable, wi.z, s.roughness));
    const vec3 f0 = s.base;
    const vec3 metal = (f0 + (vec3(1.0) - f0) * fresnel) * lobe.x * (vec3(1.0) + f0 * lost);
    const vec3 layer = s.specular * (o.f0 + (vec3(1.0) - o.f0) * fresnel) * lobe.x * (vec3(1.0) + o.f0 * lost);
    const vec3 rest = kPi * (vec3(1.0) - s.specular * o.layerAverage);
    vec3 left = (vec3(1.0) - s.specular * o.layerAlbedo) * (vec3(1.0) - s.specular * layerAlbedo(o.f0, eIn, wIn)) / rest;
    left = mix(vec3(0.0), left, greaterThan(rest, vec3(1e-6)));
    return BsdfValue((layer + s.base * left) * (1.0 - s.metallic) + metal * s.metallic,
                     o.pick * lobe.z + (1.0 - o.pick) * wi.z / kPi);
}

// evalWith: the coat over the base (without one, the base's exactly).
BsdfValue evalWith(WavefrontParams p, Surface s, BsdfOutgoing o, vec3 wo, vec3 wi) {
    const BsdfValue base = evalBase(p, s, o, wo, wi);
    if (!(s.clearcoat > 0.0) || wi.z <= 0.0) return base;
    const vec3 coatWi = coatIn(o, wi);
    const vec3 under = base.f * (1.0 - s.clearcoat * o.coatAlbedo);
    if (coatWi.z <= 0.0) return BsdfValue(under, (1.0 - o.coatPick) * base.pdf);  // below the coat (tilted only)
    const vec3 lobe = microfacetLobe(o.coatWo, coatWi, o.coatAlpha);
    const float fresnel = kDielectricF0 + (1.0 - kDielectricF0) * schlickWeight(lobe.y);
    float coat = s.clearcoat * fresnel * lobe.x * (1.0 + kDielectricF0 * (1.0 / o.coatMetalAlbedo - 1.0));
    if (o.coatTilted) coat *= coatWi.z / wi.z;  // the caller's cosine is the base's
    return BsdfValue(under + vec3(coat), o.coatPick * lobe.z + (1.0 - o.coatPick) * base.pdf);
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
    const BsdfValue v = evalWith(p, s, outgoingTerms(p, s, wo, localCoatNormal(s, tangent, bitangent)), wo, local);
    pdf = v.pdf;
    return v.f * local.z;
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
    const BsdfOutgoing o = outgoingTerms(p, s, wo, localCoatNormal(s, tangent, bitangent));
    vec3 wi;
    const float uLobe = randomFloat(pixel, sampleIndex, bounce, kDimLobe, p.seed);
    if (uLobe < o.coatPick) {
        const vec3 h = sampleVisibleNormal(o.coatWo, o.coatAlpha, u1, u2);
        const vec3 coatWi = h * (2.0 * dot(o.coatWo, h)) - o.coatWo;
        if (coatWi.z <= 0.0) return false;  // below the coat, where its lobe has no density
        wi = normalize(coatOut(o, coatWi));
    } else if ((o.coatPick > 0.0 ? (uLobe - o.coatPick) / (1.0 - o.coatPick) : uLobe) < o.pick) {
        const vec3 h = sampleVisibleNormal(wo, o.alpha, u1, u2);
        wi = normalize(h * (2.0 * dot(wo, h)) - wo);
    } else {
        const float r = sqrt(u1);
        const float phi = 2.0 * kPi * u2;
        wi = vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u1)));
    }
    if (wi.z <= 0.0) return false;
    const BsdfValue v = evalWith(p, s, o, wo, wi);
    pdf = v.pdf;
    if (!(pdf > 0.0)) return false;
    weight = v.f * (wi.z / pdf);
    if (any(isinf(weight)) || any(isnan(weight))) return false;
    direction = normalize(tangent * wi.x + bitangent * wi.y + s.ns * wi.z);
    return dot(direction, s.n) > 0.0;
}

#endif  // VASTRAY_MICROFACET_GLSL

#include "vastray/core/Microfacet.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "vastray/core/Sampling.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

constexpr float kMinCosine = 1e-6f;

float alphaOf(float roughness) { return std::fmax(roughness * roughness, kMinMicrofacetAlpha); }

// Smith's Lambda for the GGX distribution: tan^2 from the components, no 1 - cos^2.
float smithLambda(Vec3f w, float alpha) {
    const float z = std::fmax(w.z, kMinCosine);
    const float tan2 = (w.x * w.x + w.y * w.y) / (z * z);
    return 0.5f * (std::sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}

// GGX D(h) with 1 - cos^2 theta taken as h.x^2 + h.y^2 (exact near the peak in fp32).
float ggxD(Vec3f h, float alpha) {
    const float a2 = alpha * alpha;
    const float t = h.x * h.x + h.y * h.y + a2 * h.z * h.z;
    return a2 / (kPi * t * t);
}

float schlickWeight(float cosine) {
    const float c = 1.0f - std::clamp(cosine, 0.0f, 1.0f);
    const float c2 = c * c;
    return c2 * c2 * c;
}

// Dupuy and Benyoub 2023: a visible normal of the GGX distribution seen from wo (wo.z > 0).
Vec3f sampleVisibleNormal(Vec3f wo, float alpha, float u1, float u2) {
    const Vec3f stretched = normalize(Vec3f{wo.x * alpha, wo.y * alpha, wo.z});
    const float phi = 2.0f * kPi * u1;
    const float z = (1.0f - u2) * (1.0f + stretched.z) - stretched.z;
    const float sinTheta = std::sqrt(std::clamp(1.0f - z * z, 0.0f, 1.0f));
    const Vec3f h = Vec3f{sinTheta * std::cos(phi), sinTheta * std::sin(phi), z} + stretched;
    return normalize(Vec3f{h.x * alpha, h.y * alpha, std::fmax(h.z, 0.0f)});
}

// The lobe's single-scattering terms: D G2 / (4 mu_o mu_i), the half vector's cosine to wo, and
// the visible-normal density of wi (G1(wo) D / (4 mu_o)). wo.z and wi.z > 0.
struct Lobe {
    float specular = 0, cosineOH = 0, pdf = 0;
};
Lobe lobeAt(Vec3f wo, Vec3f wi, float alpha) {
    Lobe l;
    const Vec3f h = normalize(wo + wi);
    const float d = ggxD(h, alpha);
    const float lambdaO = smithLambda(wo, alpha), lambdaI = smithLambda(wi, alpha);
    l.specular = d / (4.0f * wo.z * wi.z * (1.0f + lambdaO + lambdaI));
    l.cosineOH = dot(wo, h);
    l.pdf = d / (4.0f * wo.z * (1.0f + lambdaO));
    return l;
}

// The single-scattering albedo of Schlick's weight alone, from E and Ed(0.04) at one (mu, r):
// Ed = (0.04 E + 0.96 W) (1 + 0.04 (1 / E - 1)).
float fresnelWeightAlbedo(float e, float ed) {
    return (ed / (1.0f + kDielectricF0 * (1.0f / e - 1.0f)) - kDielectricF0 * e) / (1.0f - kDielectricF0);
}

// The compensated layer's albedo for normal-incidence reflectance f0: (f0 E + (1 - f0) W)
// (1 + f0 (1 / E - 1)), 1 at f0 = 1, Ed at f0 = 0.04.
float layerAlbedo(float f0, float e, float w) { return (f0 * e + (1.0f - f0) * w) * (1.0f + f0 * (1.0f / e - 1.0f)); }

// The dielectric layer's F0 per channel: min(F0(ior) specularColor, 1).
Vec3f layerF0(const Bsdf& b) {
    Vec3f f0;
    for (int c = 0; c < 3; ++c) f0[c] = std::fmin(b.dielectricF0 * b.specularColor[c], 1.0f);
    return f0;
}

// The coat normal's frame (Bsdf::coatNormal): tilted false when it is +z, and then every
// direction is its own in it.
struct CoatFrame {
    bool tilted = false;
    Frame frame;
    Vec3f in(Vec3f v) const {
        return tilted ? frame.toLocal(v) : v;
    }
    Vec3f out(Vec3f v) const { return tilted ? frame.toWorld(v) : v; }
};
CoatFrame coatFrameOf(const Bsdf& b) {
    CoatFrame c;
    c.tilted = !(b.coatNormal == Vec3f{0, 0, 1});
    if (c.tilted) c.frame = frameAround(b.coatNormal);
    return c;
}

// What depends on wo alone, looked up once per shading event: alpha, E(mu_o), the layer's albedo
// per channel at mu_o and its cosine-weighted average, and the probability of drawing the
// specular lobe (its albedo's share of the two lobes').
struct Outgoing {
    float alpha = 0, metalAlbedo = 0, pick = 0;
    Vec3f f0, layerAlbedo, layerAverage;
    // The coat (clearcoat > 0): alpha, E and Ed at its roughness and mu_o, and its lobe's pick;
    // its frame and wo in it (lifted to a grazing 1e-4 when the coat normal turns wo below it).
    float coatAlpha = 0, coatMetalAlbedo = 1, coatAlbedo = 0, coatPick = 0;
    CoatFrame coat;
    Vec3f coatWo;
};
Outgoing outgoingTerms(const Bsdf& b, Vec3f wo, const float* tables) {
    Outgoing o;
    o.coatWo = wo;
    o.alpha = alphaOf(b.roughness);
    o.metalAlbedo = microfacetTableLookup(tables + kMicrofacetMetalTable, wo.z, b.roughness);
    const float w = fresnelWeightAlbedo(
        o.metalAlbedo, microfacetTableLookup(tables + kMicrofacetDielectricTable, wo.z, b.roughness));
    const float wAverage = microfacetAverageLookup(tables, b.roughness, kMicrofacetFresnelAverageTable);
    const float mixAverage = microfacetAverageLookup(tables, b.roughness, kMicrofacetMixAverageTable);
    o.f0 = layerF0(b);
    for (int c = 0; c < 3; ++c) {
        const float f0 = o.f0[c];
        o.layerAlbedo[c] = layerAlbedo(f0, o.metalAlbedo, w);
        o.layerAverage[c] = f0 * f0 + (1.0f - f0) * (1.0f - f0) * wAverage + f0 * (1.0f - f0) * mixAverage;
    }
    const float base = (b.base.x + b.base.y + b.base.z) / 3.0f;
    const float layer = (o.layerAlbedo.x + o.layerAlbedo.y + o.layerAlbedo.z) / 3.0f;
    float left = 0;
    for (int c = 0; c < 3; ++c) left += b.base[c] * (1.0f - b.specular * o.layerAlbedo[c]) / 3.0f;
    const float spec = (1.0f - b.metallic) * b.specular * layer + b.metallic * base;
    const float diffuse = (1.0f - b.metallic) * left;
    o.pick = spec + diffuse > 0.0f ? spec / (spec + diffuse) : 0.5f;
    if (b.clearcoat > 0.0f) {
        o.coat = coatFrameOf(b);
        if (o.coat.tilted) {
            o.coatWo = o.coat.in(wo);
            if (o.coatWo.z < 1e-4f) o.coatWo = normalize(Vec3f{o.coatWo.x, o.coatWo.y, 1e-4f});
        }
        o.coatAlpha = alphaOf(b.clearcoatRoughness);
        o.coatMetalAlbedo = microfacetTableLookup(tables + kMicrofacetMetalTable, o.coatWo.z, b.clearcoatRoughness);
        o.coatAlbedo = microfacetTableLookup(tables + kMicrofacetDielectricTable, o.coatWo.z, b.clearcoatRoughness);
        const float coat = b.clearcoat * o.coatAlbedo, under = (1.0f - coat) * (spec + diffuse);
        o.coatPick = coat + under > 0.0f ? coat / (coat + under) : 1.0f;
    }
    return o;
}

// The base (everything under the coat): f and the mixture's density from one lobe evaluation;
// wo.z > 0.
BsdfValue evalBase(const Bsdf& b, const Outgoing& o, Vec3f wo, Vec3f wi, const float* tables) {
    if (wi.z <= 0) return {};
    const Lobe lobe = lobeAt(wo, wi, o.alpha);
    const float fresnel = schlickWeight(lobe.cosineOH);
    const float lost = 1.0f / o.metalAlbedo - 1.0f;
    const float eIn = microfacetTableLookup(tables + kMicrofacetMetalTable, wi.z, b.roughness);
    const float wIn = fresnelWeightAlbedo(eIn, microfacetTableLookup(tables + kMicrofacetDielectricTable, wi.z, b.roughness));
    // Metal: Fresnel(base) specular (1 + base (1 / E - 1)), per channel. Dielectric: s Fresnel(F0)
    // specular, compensated, plus the diffuse base of what it leaves (none where it leaves nothing).
    Vec3f metal, dielectricPart;
    for (int c = 0; c < 3; ++c) {
        const float f0 = b.base[c];
        metal[c] = (f0 + (1.0f - f0) * fresnel) * lobe.specular * (1.0f + f0 * lost);
        const float d0 = o.f0[c];
        const float layer = b.specular * (d0 + (1.0f - d0) * fresnel) * lobe.specular * (1.0f + d0 * lost);
        const float rest = kPi * (1.0f - b.specular * o.layerAverage[c]);
        const float left = rest > 1e-6f ? (1.0f - b.specular * o.layerAlbedo[c]) *
                                              (1.0f - b.specular * layerAlbedo(d0, eIn, wIn)) / rest
                                        : 0.0f;
        dielectricPart[c] = layer + b.base[c] * left;
    }
    return {dielectricPart * (1.0f - b.metallic) + metal * b.metallic,
            o.pick * lobe.pdf + (1.0f - o.pick) * wi.z / kPi};
}

// f and the density with the coat over the base (without one, the base's exactly).
BsdfValue evalWith(const Bsdf& b, const Outgoing& o, Vec3f wo, Vec3f wi, const float* tables) {
    const BsdfValue base = evalBase(b, o, wo, wi, tables);
    if (!(b.clearcoat > 0.0f) || wi.z <= 0) return base;
    const Vec3f coatWi = o.coat.in(wi);
    const Vec3f under = base.f * (1.0f - b.clearcoat * o.coatAlbedo);
    if (coatWi.z <= 0) return {under, (1.0f - o.coatPick) * base.pdf};  // below the coat (tilted only)
    const Lobe lobe = lobeAt(o.coatWo, coatWi, o.coatAlpha);
    const float fresnel = kDielectricF0 + (1.0f - kDielectricF0) * schlickWeight(lobe.cosineOH);
    float coat = b.clearcoat * fresnel * lobe.specular * (1.0f + kDielectricF0 * (1.0f / o.coatMetalAlbedo - 1.0f));
    if (o.coat.tilted) coat *= coatWi.z / wi.z;  // the caller's cosine is the base's
    return {under + Vec3f{coat, coat, coat}, o.coatPick * lobe.pdf + (1.0f - o.coatPick) * base.pdf};
}

// A Hammersley point set of n points: (i + 1/2) / n and the base-2 radical inverse of i.
float radicalInverse(uint32_t i) {
    i = (i << 16u) | (i >> 16u);
    i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
    i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
    i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
    i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
    return float(double(i) * 0x1p-32);
}

// W at a node of the tables (the lookup's value there).
double nodeW(const std::vector<float>& t, uint32_t r, uint32_t m) {
    const uint32_t i = r * kMicrofacetTableSide + m;
    return fresnelWeightAlbedo(t[kMicrofacetMetalTable + i], t[kMicrofacetDielectricTable + i]);
}

// Integral over [0, 1] of y(mu) mu for y piecewise linear between the nodes' values.
template <class Node>
double rowAverage(uint32_t n, Node y) {
    double sum = 0;
    for (uint32_t m = 0; m + 1 < n; ++m) {
        const double a = double(m) / (n - 1), b = double(m + 1) / (n - 1);
        sum += (b - a) / 6.0 * (y(m) * (2 * a + b) + y(m + 1) * (a + 2 * b));
    }
    return sum;
}

// A row per roughness, in parallel (2,048 samples per entry: within ~0.2 % of 4,096's; the whole
// table took 0.35 s on one core with 4,096, render time a glossy render paid in every process).
std::vector<float> computeTables() {
    constexpr uint32_t n = kMicrofacetTableSide, kSamples = 2048;
    std::vector<float> t(kMicrofacetTableFloats, 0.0f);
    tbb::parallel_for(uint32_t(0), n, [&](uint32_t r) {
        const float alpha = alphaOf(float(r) / float(n - 1));
        for (uint32_t m = 0; m < n; ++m) {
            const float mu = std::fmax(float(m) / float(n - 1), 1e-3f);
            const Vec3f wo{std::sqrt(1.0f - mu * mu), 0.0f, mu};
            // Visible-normal sampling: f cos / pdf = G2 / G1(wo) times the Fresnel term.
            double plain = 0, fresnel = 0;
            for (uint32_t i = 0; i < kSamples; ++i) {
                const Vec3f h = sampleVisibleNormal(wo, alpha, (float(i) + 0.5f) / float(kSamples), radicalInverse(i));
                const Vec3f wi = h * (2.0f * dot(wo, h)) - wo;
                if (wi.z <= 0) continue;
                const float g = (1.0f + smithLambda(wo, alpha)) /
                                (1.0f + smithLambda(wo, alpha) + smithLambda(wi, alpha));
                plain += g;
                fresnel += g * (kDielectricF0 + (1.0f - kDielectricF0) * schlickWeight(dot(wo, h)));
            }
            const float e = float(plain / kSamples);
            t[kMicrofacetMetalTable + r * n + m] = e;
            t[kMicrofacetDielectricTable + r * n + m] =
                float(fresnel / kSamples) * (1.0f + kDielectricF0 * (1.0f / e - 1.0f));
        }
        // 2 * integral of the piecewise-linear Ed(mu) mu (rowAverage: on [a, b], h/6 (ya (2a + b) + yb (a + 2b))).
        t[kMicrofacetAverageTable + r] =
            float(2.0 * rowAverage(n, [&](uint32_t m) { return double(t[kMicrofacetDielectricTable + r * n + m]); }));
        t[kMicrofacetFresnelAverageTable + r] = float(2.0 * rowAverage(n, [&](uint32_t m) { return nodeW(t, r, m); }));
        t[kMicrofacetMixAverageTable + r] = float(2.0 * rowAverage(n, [&](uint32_t m) {
            const double e = t[kMicrofacetMetalTable + r * n + m];
            return e + nodeW(t, r, m) / e;
        }));
    });
    return t;
}

}  // namespace

float iorF0(float ior) {
    if (ior == 1.5f) return kDielectricF0;
    const float r = (ior - 1.0f) / (ior + 1.0f);
    return r * r;
}

std::string materialFactorProblem(const Material& m) {
    const std::pair<const char*, float> factors[] = {{"metallic", m.metallic},
                                                     {"roughness", m.roughness},
                                                     {"specular", m.specular},
                                                     {"clearcoat", m.clearcoat},
                                                     {"clearcoat roughness", m.clearcoatRoughness},
                                                     {"alpha cutoff", m.alphaCutoff}};
    for (const auto& [what, v] : factors)
        if (!(v >= 0.0f && v <= 1.0f)) {
            char text[64];
            std::snprintf(text, sizeof text, "%s %g is outside [0, 1]", what, double(v));
            return text;
        }
    if (!(m.ior == 0.0f || (m.ior >= 1.0f && m.ior <= kMaxIor))) {
        char text[96];
        std::snprintf(text, sizeof text, "ior %g is neither 0 nor in [1, %g]", double(m.ior), double(kMaxIor));
        return text;
    }
    for (float v : m.specularColor)
        if (!(v >= 0.0f && v <= kMaxSpecularColor)) {
            char text[128];
            std::snprintf(text, sizeof text, "specular colour (%g, %g, %g) is outside [0, %g]", double(m.specularColor[0]),
                          double(m.specularColor[1]), double(m.specularColor[2]), double(kMaxSpecularColor));
            return text;
        }
    return {};
}

// Isolated: the first caller is often a render's TBB task (an Embree tile); while it waits for
// the rows it must not pick up another tile, whose call would wait for this same initialization.
const std::vector<float>& microfacetTables() {
    static const std::vector<float> tables = [] {
        std::vector<float> t;
        tbb::this_task_arena::isolate([&] { t = computeTables(); });
        return t;
    }();
    return tables;
}

float microfacetTableLookup(const float* table, float mu, float roughness) {
    constexpr float last = float(kMicrofacetTableSide - 1);
    const float x = std::clamp(mu, 0.0f, 1.0f) * last, y = std::clamp(roughness, 0.0f, 1.0f) * last;
    const uint32_t x0 = std::min(uint32_t(x), kMicrofacetTableSide - 2), y0 = std::min(uint32_t(y), kMicrofacetTableSide - 2);
    const float fx = x - float(x0), fy = y - float(y0);
    const float* row0 = table + y0 * kMicrofacetTableSide + x0;
    const float* row1 = row0 + kMicrofacetTableSide;
    const float low = row0[0] + (row0[1] - row0[0]) * fx, high = row1[0] + (row1[1] - row1[0]) * fx;
    return low + (high - low) * fy;
}

float microfacetAverageLookup(const float* tables, float roughness, uint32_t table) {
    constexpr float last = float(kMicrofacetTableSide - 1);
    const float y = std::clamp(roughness, 0.0f, 1.0f) * last;
    const uint32_t y0 = std::min(uint32_t(y), kMicrofacetTableSide - 2);
    const float* row = tables + table + y0;
    return row[0] + (row[1] - row[0]) * (y - float(y0));
}

BsdfValue evalBsdf(const Bsdf& b, Vec3f wo, Vec3f wi, const float* tables) {
    if (wo.z <= 0) return {};
    return evalWith(b, outgoingTerms(b, wo, tables), wo, wi, tables);
}

bool sampleBsdf(const Bsdf& b, Vec3f wo, float uLobe, float u1, float u2, const float* tables, Vec3f* wi, Vec3f* weight,
                float* pdf) {
    if (wo.z <= 0) return false;
    const Outgoing o = outgoingTerms(b, wo, tables);
    if (uLobe < o.coatPick) {
        const Vec3f h = sampleVisibleNormal(o.coatWo, o.coatAlpha, u1, u2);
        const Vec3f coatWi = h * (2.0f * dot(o.coatWo, h)) - o.coatWo;
        if (coatWi.z <= 0) return false;  // below the coat, where its lobe has no density
        *wi = normalize(o.coat.out(coatWi));
    } else if ((o.coatPick > 0.0f ? (uLobe - o.coatPick) / (1.0f - o.coatPick) : uLobe) < o.pick) {
        const Vec3f h = sampleVisibleNormal(wo, o.alpha, u1, u2);
        *wi = normalize(h * (2.0f * dot(wo, h)) - wo);
    } else {
        *wi = cosineHemisphere(u1, u2);
    }
    if (wi->z <= 0) return false;
    const BsdfValue v = evalWith(b, o, wo, *wi, tables);
    *pdf = v.pdf;
    if (!(*pdf > 0)) return false;
    *weight = v.f * (wi->z / *pdf);
    return isFinite(*weight);
}

}  // namespace vastray

#include "vastray/core/Blackbody.h"

#include <algorithm>
#include <cmath>

namespace vastray {
namespace {

// One lobe of the fit: a Gaussian of mean `mean` with inverse widths `below` and `above` on
// each side (Wyman et al. 2013, listing 1).
double lobe(double nm, double mean, double below, double above) {
    const double t = (nm - mean) * (nm < mean ? below : above);
    return std::exp(-0.5 * t * t);
}

// Planck's spectral radiance up to the constant 2hc^2 (which the normalization cancels).
double planck(double nm, double kelvin) {
    constexpr double kC2 = 1.4387769e7;  // hc / k in nm K
    return 1.0 / (std::pow(nm, 5.0) * std::expm1(kC2 / (nm * kelvin)));
}

std::array<double, 3> xyzOf(double kelvin) {
    std::array<double, 3> xyz{0, 0, 0};
    if (!(kelvin > 0.0)) return xyz;
    for (int nm = 360; nm <= 830; ++nm) {
        const double b = planck(nm, kelvin);
        const auto c = cieXyzFit(nm);
        for (int i = 0; i < 3; ++i) xyz[i] += b * c[i];
    }
    return xyz;
}

}  // namespace

std::array<double, 3> cieXyzFit(double nm) {
    return {1.056 * lobe(nm, 599.8, 0.0264, 0.0323) + 0.362 * lobe(nm, 442.0, 0.0624, 0.0374) -
                0.065 * lobe(nm, 501.1, 0.0490, 0.0382),
            0.821 * lobe(nm, 568.8, 0.0213, 0.0247) + 0.286 * lobe(nm, 530.9, 0.0613, 0.0322),
            1.217 * lobe(nm, 437.0, 0.0845, 0.0278) + 0.681 * lobe(nm, 459.0, 0.0385, 0.0725)};
}

std::array<double, 3> blackbodySrgb(double kelvin) {
    static const double white = xyzOf(6500.0)[1];
    const auto [x, y, z] = xyzOf(kelvin);
    // XYZ to linear sRGB (IEC 61966-2-1, D65).
    const double rgb[3] = {3.2404542 * x - 1.5371385 * y - 0.4985314 * z, -0.9692660 * x + 1.8760108 * y + 0.0415560 * z,
                           0.0556434 * x - 0.2040259 * y + 1.0572252 * z};
    return {std::max(rgb[0], 0.0) / white, std::max(rgb[1], 0.0) / white, std::max(rgb[2], 0.0) / white};
}

const std::vector<float>& blackbodyTable() {
    static const std::vector<float> table = [] {
        std::vector<float> t(3 * kBlackbodyTableSize);
        const double ratio = double(kMaxTemperature) / kBlackbodyMinKelvin;
        for (uint32_t i = 0; i < kBlackbodyTableSize; ++i) {
            const auto rgb = blackbodySrgb(kBlackbodyMinKelvin * std::pow(ratio, double(i) / (kBlackbodyTableSize - 1)));
            for (int c = 0; c < 3; ++c) t[3 * i + c] = float(rgb[c]);
        }
        return t;
    }();
    return table;
}

Vec3f blackbodyRadiance(const float* table, float kelvin) {
    // In float, as the kernel computes it.
    constexpr float last = float(kBlackbodyTableSize - 1);
    const float scale = last / std::log(kMaxTemperature / kBlackbodyMinKelvin);
    const float x = kelvin > kBlackbodyMinKelvin ? std::min(std::log(kelvin / kBlackbodyMinKelvin) * scale, last) : 0.0f;
    const uint32_t i = std::min(uint32_t(x), kBlackbodyTableSize - 2);
    const float f = x - float(i);
    const float* a = table + 3 * i;
    return Vec3f{a[0], a[1], a[2]} * (1.0f - f) + Vec3f{a[3], a[4], a[5]} * f;
}

}  // namespace vastray

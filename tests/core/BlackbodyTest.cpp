// The blackbody table (core/Blackbody.h) against an independent integration of Planck's law
// (SI constants, Simpson's rule on a 0.25 nm grid) times the same CIE fit, and the colours a
// reader expects of a cool, a white and a hot body.
#include <gtest/gtest.h>

#include <cmath>

#include "vastray/core/Blackbody.h"

namespace vastray {
namespace {

// Linear sRGB (negative channels set to 0), not normalized.
std::array<double, 3> integrateSrgb(double kelvin) {
    constexpr double h = 6.62607015e-34, c = 299792458.0, k = 1.380649e-23;
    constexpr double lo = 360.0, hi = 830.0, step = 0.25;
    const int n = int((hi - lo) / step);  // even
    double xyz[3] = {0, 0, 0};
    for (int i = 0; i <= n; ++i) {
        const double nm = lo + i * step, m = nm * 1e-9;
        const double weight = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        const double radiance = 2.0 * h * c * c / (std::pow(m, 5) * (std::exp(h * c / (m * k * kelvin)) - 1.0));
        const auto cmf = cieXyzFit(nm);
        for (int j = 0; j < 3; ++j) xyz[j] += weight * step / 3.0 * radiance * cmf[j];
    }
    const double r = 3.2404542 * xyz[0] - 1.5371385 * xyz[1] - 0.4985314 * xyz[2];
    const double g = -0.9692660 * xyz[0] + 1.8760108 * xyz[1] + 0.0415560 * xyz[2];
    const double b = 0.0556434 * xyz[0] - 0.2040259 * xyz[1] + 1.0572252 * xyz[2];
    return {std::max(r, 0.0), std::max(g, 0.0), std::max(b, 0.0)};
}

double luminance6500() {
    constexpr double h = 6.62607015e-34, c = 299792458.0, k = 1.380649e-23;
    double y = 0;
    for (int i = 0; i <= 1880; ++i) {
        const double nm = 360.0 + i * 0.25, m = nm * 1e-9;
        const double weight = (i == 0 || i == 1880) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        y += weight * 0.25 / 3.0 * 2.0 * h * c * c / (std::pow(m, 5) * (std::exp(h * c / (m * k * 6500.0)) - 1.0)) *
             cieXyzFit(nm)[1];
    }
    return y;
}

TEST(Blackbody, FitMatchesTheCieTablesAtTheirPeaks) {
    // CIE 1931 2-degree values: x(600) 1.0622, y(555) 1.0000, z(450) 1.7471; the fit's error
    // near the peaks is a few percent (Wyman et al. 2013, figure 2).
    EXPECT_NEAR(cieXyzFit(600.0)[0], 1.0622, 0.03);
    EXPECT_NEAR(cieXyzFit(555.0)[1], 1.0, 0.03);
    EXPECT_NEAR(cieXyzFit(450.0)[2], 1.7471, 0.06);
}

// The table's lookup, between nodes as well as on them, within 1e-3 of the largest channel of an
// integration done another way: the 1 nm rectangle rule against Simpson on 0.25 nm (both well
// under 1e-4 on these smooth integrands) and the linear interpolation between log-spaced nodes
// (under 2e-4 from 1000 K up, core/Blackbody.h).
TEST(Blackbody, TableMatchesIndependentIntegration) {
    const double white = luminance6500();
    const float* table = blackbodyTable().data();
    for (double kelvin : {1000.0, 1234.5, 1850.0, 3000.0, 4321.0, 6500.0, 9876.0, 20000.0, 55555.0, 1e5}) {
        const auto expected = integrateSrgb(kelvin);
        const Vec3f got = blackbodyRadiance(table, float(kelvin));
        const double largest = std::max({expected[0], expected[1], expected[2]}) / white;
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], expected[c] / white, 1e-3 * largest) << kelvin << " K, channel " << c;
    }
}

TEST(Blackbody, ColoursOfCoolWhiteAndHotBodies) {
    const float* table = blackbodyTable().data();
    const Vec3f cool = blackbodyRadiance(table, 1000.0f);
    EXPECT_GT(cool.x, 10.0f * cool.y);  // deep red
    EXPECT_GT(cool.y, cool.z);
    // 6500 K: Y is 1 by definition; the Planckian locus at 6500 K, (0.3135, 0.3236), lies just
    // below D65's (0.3127, 0.3290), towards magenta: red and blue a few percent above green,
    // each channel within 5 % of white.
    const Vec3f white = blackbodyRadiance(table, 6500.0f);
    EXPECT_NEAR(0.2126f * white.x + 0.7152f * white.y + 0.0722f * white.z, 1.0f, 1e-3f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(white[c], 1.0f, 0.05f) << c;
    EXPECT_GT(white.x, white.y);
    EXPECT_GT(white.z, white.y);
    const Vec3f hot = blackbodyRadiance(table, 20000.0f);
    EXPECT_GT(hot.z, hot.y);
    EXPECT_GT(hot.y, hot.x);
    // Hotter is brighter at every wavelength, so in every channel too.
    for (int c = 0; c < 3; ++c) EXPECT_GT(hot[c], white[c]);
    // Cold bodies do not glow; temperatures past the table's end read its last node.
    EXPECT_EQ(blackbodyRadiance(table, 0.0f), Vec3f{});
    EXPECT_EQ(blackbodyRadiance(table, 2e5f), blackbodyRadiance(table, kMaxTemperature));
}

}  // namespace
}  // namespace vastray

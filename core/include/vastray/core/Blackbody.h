#pragma once
// The colour of a blackbody (docs/RENDERING.md, "Volumes"): Planck's law integrated against the
// CIE 1931 2-degree colour matching functions and converted to linear sRGB (Rec. 709 primaries,
// D65 white), normalized so that the luminance Y of 6500 K is 1. Computed once on the host into
// a table of kBlackbodyTableSize nodes that every backend reads with the same lookup
// (gpu/shaders/common/Volume.glsl's blackbodyRadiance mirrors blackbodyRadiance here).
#include <array>
#include <cstdint>
#include <vector>

#include "vastray/core/Vec3.h"

namespace vastray {

// Temperatures a temperature grid may hold, in kelvin.
constexpr float kMaxTemperature = 1e5f;
// The table's nodes: node i at kBlackbodyMinKelvin * (kMaxTemperature / kBlackbodyMinKelvin)^(i /
// (size - 1)), log-spaced because the visible radiance of a cool body grows like exp(-c2 / (lambda
// T)): linear interpolation between nodes is then within 2e-4 of the integral from 1000 K up (the
// error grows like 1 / T^2 below; at 100 K the radiance is below float's range, 0).
constexpr uint32_t kBlackbodyTableSize = 4096;
constexpr float kBlackbodyMinKelvin = 100.0f;

// Wyman, Sloan and Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Color Matching
// Functions" (JCGT 2(2)), the multi-lobe fit of the CIE 1931 2-degree functions: x, y, z at a
// wavelength in nm.
std::array<double, 3> cieXyzFit(double nanometres);

// Linear sRGB of a blackbody at `kelvin` by direct integration over 360-830 nm (1 nm steps),
// channels below 0 (colours outside the sRGB gamut) set to 0; what the table holds at its nodes.
std::array<double, 3> blackbodySrgb(double kelvin);

// kBlackbodyTableSize RGB triples (3 floats a node, node 0 first), computed on
// first use and shared by all callers.
const std::vector<float>& blackbodyTable();

// The table's value at `kelvin` (linear in the node index between the two nodes around it; the
// first node at or below kBlackbodyMinKelvin, the last at or above kMaxTemperature).
Vec3f blackbodyRadiance(const float* table, float kelvin);

}  // namespace vastray

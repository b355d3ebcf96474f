#pragma once
// Renders in the reference renderer's tests: the Embree image of a scene, and the head-on view
// of the unit quad that reads texels back through the albedo AOV.
#include <gtest/gtest.h>

#include <cstdint>
#include <utility>

#include "HeadOnView.h"
#include "vastray/core/RenderOptions.h"
#include "vastray/cpu/EmbreeRenderer.h"
#include "vastray/cpu/RenderScene.h"

namespace vastray::test {

// The image; a failed render fails the test and gives an empty image.
inline RenderImage renderEmbree(const RenderScene& scene, const RenderOptions& options) {
    auto image = renderWithEmbree(scene, options);
    EXPECT_TRUE(image) << image.message();
    return image ? std::move(*image) : RenderImage{};
}

// Looking straight at the unit quad from +z, the quad exactly filling a side x side image, with
// the albedo AOV: each pixel centre is a texel centre of a side x side texture.
inline RenderOptions headOnAlbedo(uint32_t side) {
    RenderOptions o = headOnUnitQuad(side);
    o.aovs = kAovAlbedo;
    return o;
}

}  // namespace vastray::test

#pragma once
// Shared by the gpu tests: the one Vulkan device they run on, and the meshes they trace.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "TestMeshes.h"
#include "vastray/core/KdTree.h"
#include "vastray/gpu/VulkanDevice.h"

namespace vastray::gpu::test {

// Created once per test binary. CI has lavapipe, so a missing device is a failure, not a skip.
inline const Result<std::unique_ptr<VulkanDevice>>& sharedDevice() {
    static const Result<std::unique_ptr<VulkanDevice>> device = [] {
        auto created = VulkanDevice::create();
        if (created) std::printf("gpu tests run on: %s\n", (*created)->info().name.c_str());
        return created;
    }();
    return device;
}

#define VASTRAY_REQUIRE_DEVICE(name)                                                                       \
    ASSERT_TRUE(::vastray::gpu::test::sharedDevice().isOk())                                              \
        << "no usable Vulkan device; the gpu tests need one (CI: Mesa lavapipe, package mesa-vulkan-drivers): " \
        << ::vastray::gpu::test::sharedDevice().message();                                                \
    VulkanDevice& name = *::vastray::gpu::test::sharedDevice().value()

using vastray::test::makeAxisGrid;
using vastray::test::makeIcosphere;
using vastray::test::makeSoup;
using vastray::test::Mesh;
using vastray::test::randomVec;

}  // namespace vastray::gpu::test

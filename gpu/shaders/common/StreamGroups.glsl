// Camera paths, and the restart of streamed waves' groups: wf_generate.comp runs them over its
// queue of groups; wf_shade.comp (kKernelRestartGroups) restarts the groups whose block its shading
// ended, in the same dispatch. Include after common/WavefrontPrelude.glsl and common/Random.glsl;
// VASTRAY_SAMPLE_BATCH (default 16) sets how many samples of a group a workgroup loads side by
// side (shared memory: 16 bytes per invocation and sample).
#ifndef VASTRAY_STREAM_GROUPS_GLSL
#define VASTRAY_STREAM_GROUPS_GLSL

// Path j starts at image pixel `pixel`, sample `sampleIndex` (jittered unless an AOV ray).
void startPath(ParamsRef params, uint j, uint pixel, uint sampleIndex, bool jitter) {
    const uint seed = params.p.seed, width = params.p.imageWidth;
    float jx = 0.5, jy = 0.5;
    if (jitter) {
        jx = randomFloat(pixel, sampleIndex, 0u, kDimPixelX, seed);
        jy = randomFloat(pixel, sampleIndex, 0u, kDimPixelY, seed);
    }
    const float sx = 2.0 * (float(pixel % width) + jx) / params.p.width - 1.0;
    const float sy = 1.0 - 2.0 * (float(pixel / width) + jy) / params.p.height;
    const vec3 forward = vec3(params.p.forwardX, params.p.forwardY, params.p.forwardZ);
    const vec3 right = vec3(params.p.rightX, params.p.rightY, params.p.rightZ);
    const vec3 up = vec3(params.p.upX, params.p.upY, params.p.upZ);
    const vec3 direction = normalize(forward + right * sx + up * sy);
    const uint shadow = shadowRayIndex(params.p, j);
    Vec4Array(params.p.rayOrigin).v[j] = vec4(params.p.eyeX, params.p.eyeY, params.p.eyeZ, 0.0);  // w: cone width 0
    Vec4Array(params.p.rayDirection).v[j] = vec4(direction, kInfinity);
    UVec2Array(params.p.rayState).v[j] = uvec2(kRayPending, 0u);
    UVec2Array(params.p.rayState).v[shadow] = uvec2(0u);
    Vec4Array(params.p.throughput).v[j] = vec4(1.0, 1.0, 1.0, 0.0);
    Vec4Array(params.p.radiance).v[j] = vec4(0.0, 0.0, 0.0, params.p.cameraSpread);  // w: the ray cone's spread
    const uint walks = jitter ? kWalkClosest : 0u;  // an AOV ray belongs to no path to shade
    UVec2Array(params.p.pathInfo).v[j] = uvec2(pixel, pathWord(kPathAlive | walksInWord(params.p, walks), 0u, sampleIndex));
    startWalksApart(params.p, j, walks);
}

// Streamed waves: a workgroup's groups (a thread each: `live`, group g) add their finished
// blocks and start their next ones. The paths' samples are read and their new states written by
// the whole workgroup together, kSampleBatch samples of a group side by side, so that
// neighbouring invocations touch neighbouring paths: with the state in host memory
// (PathStateMemory::Host) a thread walking its group's paths alone made a small transfer across
// the bus per path and array. The sums are the same additions in the same order.
#ifndef VASTRAY_SAMPLE_BATCH
#define VASTRAY_SAMPLE_BATCH 16u
#endif
const uint kSampleBatch = VASTRAY_SAMPLE_BATCH;
shared vec4 batchSamples[kWavefrontWorkgroupSize * kSampleBatch];  // radiance, camera hit
shared uint groupFirst[kWavefrontWorkgroupSize], groupPixel[kWavefrontWorkgroupSize], groupNext[kWavefrontWorkgroupSize],
    groupCount[kWavefrontWorkgroupSize], groupAt[kWavefrontWorkgroupSize];
shared uint batchMax;
// The window's open tiles (StreamWindow::tiles), loaded once per workgroup: a group looking for
// its next pixel scans them in order, and from shared memory the scan waits on one load, not one
// a tile.
shared uint windowTiles[4u * kMaxWindowTiles];
shared uint windowTileCount;

// The largest of the workgroup's `count`s (every invocation must call it).
uint workgroupMax(uint count) {
    if (gl_LocalInvocationIndex == 0u) batchMax = 0u;
    barrier();
    atomicMax(batchMax, count);
    barrier();
    const uint m = batchMax;
    barrier();
    return m;
}

// Path and group state that other workgroups wrote in the same dispatch (wf_shade.comp's
// restarts: the ended paths' radiance and words, the group's count): read past any incoherent
// cache, after the group's count reached zero.
layout(buffer_reference, std430, buffer_reference_align = 16) coherent buffer CoherentVec4Array { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) coherent buffer CoherentUVec2Array { uvec2 v[]; };

// Group g (when `live`) adds its finished block (its count is zero) to its pixel's sum, in sample
// order, writes the pixel's mean when that was its last block, and starts the pixel's next block
// or the window's next pixel; its paths join queue walkQueue. A group the window has no pixel
// for (or an idle one that finds none) goes to queue idleQueue. Every invocation of the
// workgroup must call it (it has barriers).
void restartGroups(ParamsRef params, bool live, uint g, uint walkQueue, uint idleQueue) {
    if (workgroupMax(live ? 1u : 0u) == 0u) return;
    const uint lt = gl_LocalInvocationIndex, groupSize = pc.sampleCount, spp = params.p.samplesPerPixel;
    const uint first = g * groupSize;
    StreamRef window = StreamRef(params.p.stream);
    // Coherent: in wf_shade the group's count reached zero through other workgroups' atomics in
    // this dispatch, and a cache line read earlier (a neighbouring group's) may hold it stale.
    CoherentUVec2Array states = CoherentUVec2Array(params.p.groupState);
    Vec4Array accum = Vec4Array(params.p.accum);
    CoherentVec4Array radiance = CoherentVec4Array(params.p.radiance);
    CoherentUVec2Array pathInfo = CoherentUVec2Array(params.p.pathInfo);
    uvec2 state = live ? states.v[g] : uvec2(kGroupIdle);
    // A group whose block is done adds it to its pixel's sum, one sample at a time.
    uint pixel = 0u, done = 0u, samples = 0u;
    if (live && state.x == 0u) {
        const uvec2 info = pathInfo.v[first];
        pixel = info.x, done = pathSample(info.y);
        samples = min(groupSize, spp - done);
    }
    if (lt == 0u) windowTileCount = window.w.tileCount;
    for (uint i = lt; i < 4u * kMaxWindowTiles; i += kWavefrontWorkgroupSize) windowTiles[i] = window.w.tiles[i];
    groupFirst[lt] = first, groupCount[lt] = samples;
    const uint most = workgroupMax(samples);
    vec4 sum = samples > 0u ? accum.v[g] : vec4(0.0);
    for (uint s0 = 0u; s0 < most; s0 += kSampleBatch) {
        for (uint i = lt; i < kWavefrontWorkgroupSize * kSampleBatch; i += kWavefrontWorkgroupSize) {
            const uint owner = i / kSampleBatch, s = s0 + i % kSampleBatch;
            if (s < groupCount[owner]) {
                const uint path = groupFirst[owner] + s;
                const bool hit = (pathInfo.v[path].y & kPathCameraHit) != 0u;
                batchSamples[i] = vec4(radiance.v[path].xyz, hit ? 1.0 : 0.0);
            }
        }
        barrier();
        for (uint i = 0u; i < kSampleBatch && s0 + i < samples; ++i) {
            const vec4 v = batchSamples[lt * kSampleBatch + i];
            sum.xyz += v.xyz;
            sum.w += v.w;
        }
        barrier();
    }
    uint next = 0u, started = 0u;
    bool idle = false;
    if (samples > 0u) {
        accum.v[g] = sum;
        next = done + samples;
        if (next >= spp) {  // the pixel is done
            Vec4Array(params.p.outColor).v[state.y] = pixelMean(params, sum);
            atomicAdd(window.w.done[state.y / params.p.tilePixels], 1u);
            state.x = kGroupIdle;
        }
    }
    if (live && state.x == kGroupIdle) {  // the window's next pixel
        const uint k = atomicAdd(window.w.cursor, 1u);
        uint start = 0u, tile = 0u;
        while (tile < windowTileCount && k >= start + windowTiles[4u * tile + 2u]) start += windowTiles[4u * tile + 2u], ++tile;
        if (tile == windowTileCount) {  // none left now (the host rewinds the cursor to the window's end)
            states.v[g] = uvec2(kGroupIdle);
            idle = true;
        } else {
            const uint local = k - start, tileWidth = windowTiles[4u * tile + 1u];
            pixel = windowTiles[4u * tile] + (local / tileWidth) * params.p.imageWidth + local % tileWidth;
            state.y = windowTiles[4u * tile + 3u] * params.p.tilePixels + local;
            next = 0u;
            accum.v[g] = vec4(0.0);
        }
    }
    if (live && !idle) {
        started = min(groupSize, spp - next);
        states.v[g] = uvec2(started, state.y);
    }
    // The started paths, written side by side, and their entries in the walk queue.
    const uint at = reserveInQueue(params, walkQueue, true, started);
    groupFirst[lt] = first, groupPixel[lt] = pixel, groupNext[lt] = next, groupCount[lt] = started, groupAt[lt] = at;
    const uint width = workgroupMax(started);
    RwUintArray queue = queueOf(params, walkQueue);
    for (uint i = lt; i < kWavefrontWorkgroupSize * width; i += kWavefrontWorkgroupSize) {
        const uint owner = i / width, s = i % width;
        if (s < groupCount[owner]) {
            startPath(params, groupFirst[owner] + s, groupPixel[owner], groupNext[owner] + s, true);
            queue.v[groupAt[owner] + s] = groupFirst[owner] + s;
        }
    }
    appendToQueue(params, idleQueue, false, idle ? 1u : 0u, g, 0u);
}
#endif  // VASTRAY_STREAM_GROUPS_GLSL

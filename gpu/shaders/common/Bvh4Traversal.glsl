// Traversal of a resident chunk's 4-wide BVH (core/Bvh4.h): closest hit, or with anyHit the
// first hit found. Each node's four child boxes are decoded from 8-bit offsets (exact products,
// one rounded sum) and tested at once; the boxes hit are visited nearest first, the others wait
// on a stack of three entries per level. Box tests widen every plane distance by the same margin
// as the KD walk (absolute part from the chunk's bounds, relative part 1e-5 of t), which covers
// the rounding of the decoded boxes, so a triangle is never missed because its box was.
// Triangles are stored in leaf order: a leaf is a range. Ties (same t, same facing) go to the
// lower sorted vertex indices, which do not depend on the tree: a chunk built with other leaf
// sizes gives the same hits. Included after common/KdTraversal.glsl.
#ifndef VASTRAY_BVH4_TRAVERSAL_GLSL
#define VASTRAY_BVH4_TRAVERSAL_GLSL

const uint kBvh4EmptyChild = 0xFFFFFFFFu;
const uint kBvh4LeafBit = 0x80000000u;
const uint kBvh4NodeWords = 14u;  // sizeof(Bvh4Node) / 4
const float kBvhInf = 1.0 / 0.0;  // +inf (constant folded)

uint bvhStackWord[kBvh4StackSize];
float bvhStackT[kBvh4StackSize];

vec4 margin4(TraversalRay r, vec4 t) {
    precise vec4 relative = r.slack + kRelativeMargin * abs(t);
    return mix(relative, vec4(r.slack), bvec4(uvec4(isinf(t)) | uvec4(isnan(t))));
}

vec4 bytes4(uint w) { return vec4((uvec4(w) >> uvec4(0u, 8u, 16u, 24u)) & 255u); }

// The child boxes' parametric entry (with margin, at least tLo) and whether each is hit within
// [tLo, tHi]; a miss gets entry +inf.
vec4 childEntries(UintArray nodes, uint base, TraversalRay r, float tLo, float tHi) {
    vec4 near = vec4(-kBvhInf), far = vec4(kBvhInf);
    bvec4 outside = bvec4(false);
    const uint exponents = nodes.v[base + 3u];
    for (int a = 0; a < 3; ++a) {
        const float origin = uintBitsToFloat(nodes.v[base + uint(a)]);
        const float scale = uintBitsToFloat(((exponents >> (8u * uint(a))) & 255u) << 23);
        precise vec4 lo = origin + bytes4(nodes.v[base + 4u + uint(a)]) * scale;
        precise vec4 hi = origin + bytes4(nodes.v[base + 7u + uint(a)]) * scale;
        if (r.direction[a] == 0.0) {
            outside = bvec4(uvec4(lessThan(vec4(r.origin[a]), lo)) | uvec4(greaterThan(vec4(r.origin[a]), hi)) |
                            uvec4(outside));
            continue;
        }
        precise vec4 tl = (lo - r.origin[a]) * r.invDirection[a];
        precise vec4 th = (hi - r.origin[a]) * r.invDirection[a];
        near = max(near, min(tl, th));
        far = min(far, max(tl, th));
    }
    precise vec4 entry = max(near - margin4(r, near), vec4(tLo));
    precise vec4 exit = min(far + margin4(r, far), vec4(tHi));
    const bvec4 hit = bvec4(uvec4(lessThanEqual(entry, exit)) & ~uvec4(outside) & uvec4(lessThan(entry, vec4(kBvhInf))));
    return mix(vec4(kBvhInf), entry, hit);
}

void orderPair(inout float ka, inout uint wa, inout float kb, inout uint wb) {
    if (kb < ka) {
        const float k = ka;
        ka = kb, kb = k;
        const uint w = wa;
        wa = wb, wb = w;
    }
}

void pushChild(inout uint sp, float entry, uint word) {
    if (entry == kBvhInf) return;
    bvhStackWord[sp] = word, bvhStackT[sp] = entry;
    ++sp;
}

TraceHit traverseBvh4(ChunkView c, TraversalRay ray, float tMin, float tMax, bool anyHit) {
    TraceHit best = TraceHit(0.0, 0.0, 0.0, 0u, 0u, 0u, 0u, 0u);
    TraversalRay r;
    float t0, t1;
    if (!enterChunk(c, ray, tMin, tMax, r, t0, t1)) return best;
    UintArray nodes = UintArray(c.nodes);
    bool found = false;
    uint sp = 0u, word = 0u;
    // One loop, no nested one: lavapipe (Mesa 22) left the outer loop after a `break` out of an
    // inner pop loop. A popped entry that a hit has culled becomes kBvh4EmptyChild (no work).
    for (;;) {
        if (word == kBvh4EmptyChild) {
        } else if ((word & kBvh4LeafBit) != 0u) {
            const uint first = word & 0x7FFFFFFu, count = ((word >> 27) & 15u) + 1u;
            for (uint tri = first; tri < first + count; ++tri)
                if (testTriangle(c, r, tri, tMin, tMax, true, best, found) && anyHit) return best;
        } else {
            ++best.nodesVisited;
            const uint base = word * kBvh4NodeWords;
            const vec4 e = childEntries(nodes, base, r, t0, found ? cppMin(best.t, t1) : t1);
            uint w0 = nodes.v[base + 10u], w1 = nodes.v[base + 11u], w2 = nodes.v[base + 12u], w3 = nodes.v[base + 13u];
            // An empty slot's box is inverted, which the slab test does not reject by itself.
            float k0 = w0 == kBvh4EmptyChild ? kBvhInf : e.x, k1 = w1 == kBvh4EmptyChild ? kBvhInf : e.y;
            float k2 = w2 == kBvh4EmptyChild ? kBvhInf : e.z, k3 = w3 == kBvh4EmptyChild ? kBvhInf : e.w;
            orderPair(k0, w0, k1, w1);
            orderPair(k2, w2, k3, w3);
            orderPair(k0, w0, k2, w2);
            orderPair(k1, w1, k3, w3);
            orderPair(k1, w1, k2, w2);
            pushChild(sp, k3, w3);
            pushChild(sp, k2, w2);
            pushChild(sp, k1, w1);
            if (k0 != kBvhInf) {
                word = w0;
                continue;
            }
        }
        if (sp == 0u) break;
        --sp;
        word = found && best.t < bvhStackT[sp] ? kBvh4EmptyChild : bvhStackWord[sp];
    }
    return best;
}

#endif  // VASTRAY_BVH4_TRAVERSAL_GLSL

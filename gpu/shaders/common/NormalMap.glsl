// Tangent-space normal maps: the GLSL twin of core/NormalMap.h (docs/RENDERING.md, "Normal
// maps"), its steps in the same order, `precise`; and the UV transform of core/MaterialTextures.h.
#ifndef VASTRAY_NORMAL_MAP_GLSL
#define VASTRAY_NORMAL_MAP_GLSL

// applyUvTransform (core/MaterialTextures.h): each product and sum rounded on its own, as the host's.
vec2 mapUv(float t[6], vec2 uv) {
    precise float u = t[0] * uv.x + t[1] * uv.y;
    precise float v = t[3] * uv.x + t[4] * uv.y;
    precise float tu = u + t[2];
    precise float tv = v + t[5];
    return vec2(tu, tv);
}

// core/NormalMap.h's uvDerivatives: dp/du and dp/dv of triangle (p0, p1, p2) with texture
// coordinates t0, t1, t2 mapped by transform t; zero (no frame) when the UVs span no area or a
// derivative is not finite.
void uvDerivatives(float t[6], vec3 p0, vec3 p1, vec3 p2, vec2 t0, vec2 t1, vec2 t2, out vec3 dpdu, out vec3 dpdv) {
    const vec2 a = mapUv(t, t0), b = mapUv(t, t1), c = mapUv(t, t2);
    precise float du1 = b.x - a.x, dv1 = b.y - a.y;
    precise float du2 = c.x - a.x, dv2 = c.y - a.y;
    precise float det = du1 * dv2 - dv1 * du2;
    dpdu = vec3(0.0), dpdv = vec3(0.0);
    if (!(det != 0.0) || isinf(det) || isnan(det)) return;
    precise float r = 1.0 / det;
    precise vec3 e1 = p1 - p0;
    precise vec3 e2 = p2 - p0;
    precise vec3 u = (e1 * dv2 - e2 * dv1) * r;
    precise vec3 v = (e2 * du1 - e1 * du2) * r;
    if (any(isinf(u)) || any(isnan(u)) || any(isinf(v)) || any(isnan(v))) return;
    dpdu = u, dpdv = v;
}

// core/NormalMap.h's perturbNormal: `normal` (unit, front side) bent by tangent-space `local` in
// the frame of dp/du, dp/dv (zero: none, the normal unchanged).
vec3 perturbNormal(vec3 normal, vec3 dpdu, vec3 dpdv, vec3 local) {
    if ((dpdu == vec3(0.0) && dpdv == vec3(0.0)) || any(isinf(local)) || any(isnan(local)) ||
        (local.x == 0.0 && local.y == 0.0 && local.z > 0.0))
        return normal;
    precise vec3 along = dpdu - normal * dot(normal, dpdu);
    const float alongLength = length(along);
    if (!(alongLength > 0.0) || isinf(alongLength)) return normal;
    precise vec3 tangent = along * (1.0 / alongLength);
    vec3 bitangent = cross(normal, tangent);
    if (dot(bitangent, dpdv) > 0.0) bitangent = -bitangent;  // up the image is -dp/dv
    precise vec3 bent = tangent * local.x + bitangent * local.y + normal * local.z;
    const float bentLength = length(bent);
    if (!(bentLength > 0.0) || isinf(bentLength)) return normal;
    return bent * (1.0 / bentLength);
}

#endif  // VASTRAY_NORMAL_MAP_GLSL

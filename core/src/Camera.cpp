#include "vastray/core/Camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "vastray/core/Utf8.h"
#include "vastray/core/VecMath.h"

namespace vastray {
namespace {

constexpr float kDegrees = 3.14159265358979323846f / 180.0f;

std::string describe(Vec3f v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

}  // namespace

std::string storedCameraName(const std::string& name) { return cutUtf8(name, kMaxSceneCameraNameBytes); }

Status checkFov(float fovYDegrees) {
    if (fovYDegrees >= kMinFovDegrees && fovYDegrees < 180.0f) return Status::ok();
    char text[96];
    std::snprintf(text, sizeof text, "camera fov %g is outside [%g, 180) degrees", double(fovYDegrees),
                  double(kMinFovDegrees));
    return Status::error(text);
}

Status validateCamera(const Camera& c) {
    if (!isFinite(c.eye)) return Status::error("camera eye is not finite: " + describe(c.eye));
    if (!isFinite(c.target)) return Status::error("camera target is not finite: " + describe(c.target));
    if (!isFinite(c.up)) return Status::error("camera up is not finite: " + describe(c.up));
    VASTRAY_TRY(checkFov(c.fovYDegrees));
    const Vec3f view = c.target - c.eye;
    if (!(length(view) > 0.0f)) return Status::error("camera eye equals target " + describe(c.eye));
    const Vec3f side = cross(normalize(view), normalize(c.up));
    if (!(length(side) > 1e-6f))
        return Status::error("camera up " + describe(c.up) + " is parallel to the view direction");
    return Status::ok();
}

Vec3f rotateFromYUp(Vec3f up, Vec3f v) {
    const Vec3f u = normalize(up);
    const float c = u.y;  // cos of the angle between +Y and u
    if (c > 1.0f - 1e-7f) return v;
    if (c < -1.0f + 1e-7f) return {v.x, -v.y, -v.z};  // a half turn about X
    // Rodrigues about k = (Y x u) / |Y x u| = (u.z, 0, -u.x) / s, with sin = s.
    const float s = std::sqrt(u.x * u.x + u.z * u.z);
    const Vec3f k{u.z / s, 0.0f, -u.x / s};
    return v * c + cross(k, v) * s + k * (dot(k, v) * (1.0f - c));
}

Camera frameBounds(const Aabb& bounds, float fovYDegrees, float aspect, Vec3f up) {
    Camera camera;
    camera.fovYDegrees = fovYDegrees;
    camera.up = up;
    Vec3f centre{0, 0, 0};
    float radius = 1.0f;
    if (!bounds.isEmpty()) {
        centre = (bounds.lo + bounds.hi) * 0.5f;
        radius = std::fmax(0.5f * length(bounds.extent()), 1e-6f);
    }
    // The bounding sphere must fit the narrower of the two fields of view.
    const float halfY = 0.5f * fovYDegrees * kDegrees;
    const float halfX = std::atan(std::tan(halfY) * aspect);
    const float distance = 1.05f * radius / std::sin(std::fmin(halfX, halfY));
    const Vec3f viewFrom = rotateFromYUp(up, normalize({0.6f, 0.5f, 1.0f}));
    camera.target = centre;
    camera.eye = centre + viewFrom * distance;
    return camera;
}

CameraRays::CameraRays(const Camera& camera, uint32_t width, uint32_t height)
    : eye_(camera.eye), width_(float(width)), height_(float(height)) {
    forward_ = normalize(camera.target - camera.eye);
    const Vec3f right = normalize(cross(forward_, camera.up));
    const Vec3f up = cross(right, forward_);
    const float halfHeight = std::tan(0.5f * camera.fovYDegrees * kDegrees);
    up_ = up * halfHeight;
    right_ = right * (halfHeight * width_ / height_);
    spread_ = 2.0f * halfHeight / height_;
}

Ray CameraRays::primary(uint32_t x, uint32_t y, float jitterX, float jitterY) const {
    const float sx = 2.0f * (float(x) + jitterX) / width_ - 1.0f;
    const float sy = 1.0f - 2.0f * (float(y) + jitterY) / height_;
    return {eye_, normalize(forward_ + right_ * sx + up_ * sy)};
}

void recordCamera(RenderImage& image, const Camera& camera, uint32_t frameWidth, uint32_t frameHeight) {
    const CameraRays rays(camera, frameWidth, frameHeight);
    const Vec3f eye = rays.eye(), f = rays.forward();
    const float halfWidth = length(rays.right()), halfHeight = length(rays.up());
    const Vec3f r = rays.right() * (1.0f / halfWidth), u = rays.up() * (1.0f / halfHeight);
    // World to camera: the rows of the basis as columns, then the eye moved to the origin.
    const float w2c[16] = {r.x, u.x, f.x, 0,  //
                           r.y, u.y, f.y, 0,  //
                           r.z, u.z, f.z, 0,  //
                           -dot(eye, r), -dot(eye, u), -dot(eye, f), 1};
    // Camera to NDC, homogeneous: x' = x / (2 halfWidth) + z / 2, y' = -y / (2 halfHeight) + z / 2,
    // w' = z, so x' / w' = (1 + x / (z halfWidth)) / 2 (CameraRays::primary's sx, from [-1, 1] to
    // [0, 1]) and y' / w' = (1 - y / (z halfHeight)) / 2 (down the image); z' = 1 (so z' / w' = 1 / z).
    const float c2n[16] = {0.5f / halfWidth, 0, 0, 0,  //
                           0, -0.5f / halfHeight, 0, 0,  //
                           0.5f, 0.5f, 0, 1,  //
                           0, 0, 1, 0};
    for (int i = 0; i < 16; ++i) image.worldToCamera[i] = w2c[i];
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            float sum = 0;
            for (int k = 0; k < 4; ++k) sum += w2c[4 * row + k] * c2n[4 * k + col];
            image.worldToNdc[4 * row + col] = sum;
        }
    image.hasCamera = true;
}

}  // namespace vastray

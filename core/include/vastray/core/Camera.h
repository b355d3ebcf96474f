#pragma once
// Pinhole camera shared by every backend. World space, y up by default; pixel (0, 0) is
// the top-left corner of the image.
#include <cstddef>
#include <cstdint>
#include <string>

#include "vastray/core/Aabb.h"
#include "vastray/core/Ray.h"
#include "vastray/core/RenderImage.h"
#include "vastray/core/Result.h"
#include "vastray/core/Vec3.h"

namespace vastray {

// The narrowest field of view: below it the framing distance (radius / tan(fov / 2)) and the
// pixel footprint leave float range (--fov 1e-30 was reported as "up is parallel").
constexpr float kMinFovDegrees = 0.001f;

// "camera fov 1e-30 is outside [0.001, 180) degrees" unless kMinFovDegrees <= fov < 180.
Status checkFov(float fovYDegrees);

struct Camera {
    Vec3f eye{0, 0, 3};
    Vec3f target{0, 0, 0};
    Vec3f up{0, 1, 0};
    float fovYDegrees = 45.0f;  // vertical field of view, in [kMinFovDegrees, 180)
};

// Finite vectors, eye != target, up not parallel to the view direction, fov in [0.001, 180).
Status validateCamera(const Camera& camera);

// A camera a scene file defines (a glTF camera node, or a camera assimp reads from a Collada,
// FBX, ... file), by the name the file gives it.
struct SceneCamera {
    std::string name;
    Camera camera;
};

// A scene camera's name holds at most this many bytes: the package's fixed name field
// (format::kCameraNameBytes). Importers store longer names cut by storedCameraName.
constexpr size_t kMaxSceneCameraNameBytes = 64;

// `name` as a package stores it: cut before its first NUL byte (the field is zero-padded), then
// to at most kMaxSceneCameraNameBytes without splitting a UTF-8 character (a name of 100 bytes
// of two-byte characters keeps 64 bytes, one of three-byte characters 63). Unchanged if it fits.
std::string storedCameraName(const std::string& name);

// A camera that sees the whole of `bounds` (its bounding sphere) from above and to the
// front-right, for a width/height aspect ratio, with `up` (need not be unit) as its up and
// "above" meaning along `up`: the Y-up view turned by rotateFromYUp.
Camera frameBounds(const Aabb& bounds, float fovYDegrees, float aspect, Vec3f up = {0, 1, 0});

// `v` turned by the smallest rotation that takes +Y onto the unit vector `up` (a half turn
// about X when `up` is -Y): a direction given for a Y-up world, in the world whose up is
// `up`. Y up: unchanged; Z up: (x, y, z) -> (x, -z, y).
Vec3f rotateFromYUp(Vec3f up, Vec3f v);

// Primary rays of one camera at one resolution. Directions are unit length, so a hit's t
// is its distance from the eye.
class CameraRays {
public:
    CameraRays(const Camera& camera, uint32_t width, uint32_t height);
    // (jitterX, jitterY) in [0, 1) place the ray inside pixel (x, y); 0.5, 0.5 is its centre.
    Ray primary(uint32_t x, uint32_t y, float jitterX, float jitterY) const;
    // The vectors primary() combines, for the device wavefront's camera kernel: the eye, the unit
    // view direction, and right and up scaled by the image plane's half width and half height.
    Vec3f eye() const { return eye_; }
    Vec3f forward() const { return forward_; }
    Vec3f right() const { return right_; }
    Vec3f up() const { return up_; }
    // A camera ray's cone spread (core/RayCone.h): the angle of a pixel at the image's centre,
    // 2 tan(fov / 2) / height.
    float coneSpread() const { return spread_; }

private:
    Vec3f eye_, forward_, right_, up_;
    float width_, height_, spread_;
};

// Records in `image` the matrices of `camera` rendering a frameWidth x frameHeight frame
// (RenderImage::worldToCamera, worldToNdc): a region of the frame keeps the whole frame's.
void recordCamera(RenderImage& image, const Camera& camera, uint32_t frameWidth, uint32_t frameHeight);

}  // namespace vastray

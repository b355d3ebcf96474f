#pragma once
#include "vastray/core/Vec3.h"

namespace vastray {

// A ray in world space; the point at parameter t is origin + t * direction.
// The direction need not be normalized, so t is measured in units of |direction|.
struct Ray {
    Vec3f origin;
    Vec3f direction;
};

}  // namespace vastray

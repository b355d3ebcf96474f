#pragma once
// The far end of an unbounded ray interval, for the tracing tests that pass one explicitly.
#include <limits>

namespace vastray::test {

inline constexpr float kInf = std::numeric_limits<float>::infinity();

}  // namespace vastray::test

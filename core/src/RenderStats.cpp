#include "vastray/core/RenderStats.h"

#include <sys/resource.h>

namespace vastray {

uint64_t peakHostBytes() {
    rusage usage{};
    if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
    return uint64_t(usage.ru_maxrss) * 1024u;  // Linux reports kilobytes
}

}  // namespace vastray

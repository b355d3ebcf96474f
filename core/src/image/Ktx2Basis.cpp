#include "Ktx2Basis.h"

#include <mutex>
#include <new>

#include <basisu_transcoder.h>

namespace vastray::ktx2 {
namespace {

// The transcoder's tables are built once per process (basisu_transcoder_init is not thread safe).
void initTranscoder() {
    static std::once_flag once;
    std::call_once(once, [] { basist::basisu_transcoder_init(); });
}

Result<std::vector<uint8_t>> transcode(const std::string& name, const std::vector<uint8_t>& bytes) {
    initTranscoder();
    const std::string at = name + ": KTX2 Basis Universal ";
    basist::ktx2_transcoder transcoder;
    if (bytes.size() > UINT32_MAX || !transcoder.init(bytes.data(), uint32_t(bytes.size())))
        return Status::error(at + "header, level index or DFD refused by the transcoder");
    if (!transcoder.is_etc1s() && !transcoder.is_uastc())
        return Status::error(at + "data is neither ETC1S nor UASTC LDR 4x4");
    if (!transcoder.start_transcoding())
        return Status::error(at + "global data (ETC1S codebooks or UASTC Zstandard level data) does not decode");
    basist::ktx2_image_level_info level;
    if (!transcoder.get_image_level_info(level, 0, 0, 0))
        return Status::error(at + "level 0 has no image");
    const uint64_t pixels = uint64_t(level.m_orig_width) * level.m_orig_height;
    std::vector<uint8_t> rgba(pixels * 4);
    if (!transcoder.transcode_image_level(0, 0, 0, rgba.data(), uint32_t(pixels),
                                          basist::transcoder_texture_format::cTFRGBA32))
        return Status::error(at + "level 0 does not transcode (its data is corrupt or truncated)");
    return rgba;
}

}  // namespace

Result<std::vector<uint8_t>> transcodeBasis(const std::string& name, const std::vector<uint8_t>& bytes) {
    try {
        return transcode(name, bytes);
    } catch (const std::bad_alloc&) {
        return Status::error(name + ": KTX2 Basis Universal level 0 does not fit in memory");
    } catch (const std::exception& e) {
        return Status::error(name + ": KTX2 Basis Universal transcoder failed: " + e.what());
    }
}

}  // namespace vastray::ktx2

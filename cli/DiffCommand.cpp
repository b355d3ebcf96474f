#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "Commands.h"
#include "vastray/core/ImageDiff.h"

namespace vastray::cli {
namespace {

// JSON has no infinity: identical images report a PSNR of null.
nlohmann::json finiteOrNull(double value) {
    return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json diffJson(const ImageDiffReport& r) {
    nlohmann::json j{{"width", r.width},
                     {"height", r.height},
                     {"channels", r.channels},
                     {"rmse", r.beautyRmse},
                     {"psnr", finiteOrNull(r.beautyPsnr)},
                     {"max_error", r.beautyMaxError}};
    if (r.hasDepth) {
        j["depth_mean_relative_error"] = r.depthMeanRelativeError;
        j["depth_hit_mismatch_pixels"] = r.depthHitMismatch;
    }
    if (r.hasPrimId) j["primid_agreement"] = r.primIdAgreement;
    return j;
}

void printHuman(const ImageDiffReport& r) {
    std::printf("%ux%u, %zu channels\n", r.width, r.height, r.channels.size());
    std::printf("  beauty RMSE          %.6g\n", r.beautyRmse);
    std::printf("  beauty PSNR          %.2f dB\n", r.beautyPsnr);
    std::printf("  beauty max error     %.6g\n", r.beautyMaxError);
    if (r.hasDepth)
        std::printf("  depth                mean relative error %.3g, %llu pixels hit in one image only\n",
                    r.depthMeanRelativeError, (unsigned long long)r.depthHitMismatch);
    if (r.hasPrimId) std::printf("  primid agreement     %.4f%%\n", 100.0 * r.primIdAgreement);
}

}  // namespace

CommandRun addDiffCommand(CLI::App& app) {
    struct Args {
        std::string a, b;
        bool json = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand(
        "diff",
        "Compare two renders: beauty RMSE/PSNR, relative depth error, primid agreement. Exit 1 when "
        "sizes or channels differ.");
    cmd->add_option("a", args->a, "first image (.exr or .png)")->required()->check(CLI::ExistingFile);
    cmd->add_option("b", args->b, "second image, the reference for relative errors")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_flag("--json", args->json, "print machine-readable JSON");
    return [args]() {
        auto report = diffImageFiles(args->a, args->b);
        if (!report) {
            std::fprintf(stderr, "vastray diff: %s\n", report.message().c_str());
            return 1;
        }
        if (args->json)
            std::printf("%s\n", diffJson(*report).dump(2).c_str());
        else
            printHuman(*report);
        return 0;
    };
}

}  // namespace vastray::cli

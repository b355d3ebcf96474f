#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "Commands.h"
#include "vastray/streamer/Generate.h"

namespace vastray::cli {

CommandRun addGenerateCommand(CLI::App& app) {
    struct Args {
        std::string kind, output;
        uint64_t triangles = 20000, seed = 1;
    };
    auto args = std::make_shared<Args>();
    CLI::App* cmd = app.add_subcommand("generate", "Write a procedural test scene as binary PLY (streamed: any size).");
    cmd->add_option("kind", args->kind, "sphere (icosphere, r=1, closed) | terrain (fBm height field) | "
                                        "soup (random overlapping triangles) | city (grid of boxes)")
        ->required();
    cmd->add_option("--triangles", args->triangles, "target triangle count (the shape decides the exact count)")
        ->required();
    cmd->add_option("-o,--output", args->output, "output file (.ply)")->required();
    cmd->add_option("--seed", args->seed, "random seed; same seed, same file")->capture_default_str();
    return [args]() {
        auto kind = parseGeneratorKind(args->kind);
        if (!kind) {
            std::fprintf(stderr, "vastray generate: %s\n", kind.message().c_str());
            return 2;
        }
        GenerateOptions options{*kind, args->triangles, args->seed};
        auto counts = generatedCounts(options);
        if (!counts) {
            std::fprintf(stderr, "vastray generate: %s\n", counts.message().c_str());
            return 2;
        }
        const auto start = std::chrono::steady_clock::now();
        if (Status s = generateToPly(options, args->output); !s) {
            std::fprintf(stderr, "vastray generate: %s\n", s.message().c_str());
            return 1;
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("wrote %s: %s, %llu triangles, %llu vertices, seed %llu (%.2f s)\n", args->output.c_str(),
                    generatorKindName(*kind), (unsigned long long)counts->triangles,
                    (unsigned long long)counts->vertices, (unsigned long long)args->seed, seconds);
        return 0;
    };
}

}  // namespace vastray::cli

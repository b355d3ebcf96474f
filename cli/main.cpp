#include <CLI/CLI.hpp>

#include <cstdio>
#include <map>
#include <string>

#include "Commands.h"

int main(int argc, char** argv) {
    CLI::App app{
        "vastray: an out-of-core renderer for triangle meshes larger than GPU memory.\n"
        "Import a mesh once into a chunked scene package (.vast), then inspect or render it."};
    app.set_version_flag("--version", "vastray " VASTRAY_VERSION);  // the CMake project's version
    app.require_subcommand(1);
    std::map<std::string, vastray::cli::CommandRun> commands{
        {"generate", vastray::cli::addGenerateCommand(app)},
        {"import", vastray::cli::addImportCommand(app)},
        {"info", vastray::cli::addInfoCommand(app)},
        {"render", vastray::cli::addRenderCommand(app)},
        {"diff", vastray::cli::addDiffCommand(app)},
        {"assemble", vastray::cli::addAssembleCommand(app)},
        {"serve", vastray::cli::addServeCommand(app)},
    };
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    for (auto& [name, run] : commands)
        if (app.got_subcommand(name)) return run();
    return 2;
}

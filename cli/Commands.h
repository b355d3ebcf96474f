#pragma once
// The `vastray` subcommands. Each registers its options on the CLI11 app and returns the
// exit code of its run: 0 success, 1 failure (message on stderr), 2 bad usage.
#include <functional>

namespace CLI {
class App;
}

namespace vastray::cli {

using CommandRun = std::function<int()>;

CommandRun addGenerateCommand(CLI::App& app);
CommandRun addImportCommand(CLI::App& app);
CommandRun addInfoCommand(CLI::App& app);
CommandRun addRenderCommand(CLI::App& app);
CommandRun addDiffCommand(CLI::App& app);
CommandRun addAssembleCommand(CLI::App& app);
CommandRun addServeCommand(CLI::App& app);

}  // namespace vastray::cli

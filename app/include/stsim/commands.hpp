#pragma once
// The subcommands of the stsim front end. Each takes the arguments after its name and returns
// the process exit code (0 ok, 1 run-time error, 2 usage error).
#include <functional>
#include <string>
#include <vector>

namespace st::cli {

struct Command {
  std::string name;
  std::string summary;
  std::function<int(int argc, const char* const* argv)> run;
};

// Every command compiled into this build, in the order `stsim --help` lists them.
std::vector<Command> allCommands();

}  // namespace st::cli

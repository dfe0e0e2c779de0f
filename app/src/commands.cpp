#include <stsim/commands.hpp>

// Each model's front end registers here; the linker brings in only what was built.
namespace st::cli {

std::vector<Command> allCommands() {
  std::vector<Command> cmds;
  return cmds;
}

}  // namespace st::cli

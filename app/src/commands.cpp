#include <stsim/commands.hpp>

namespace st::cli {

// Defined in app/src/<name>_command.cpp, compiled in when the model's library is built.
Command poolCommand();
Command armCommand();
Command highwayCommand();
Command batchCommand();

std::vector<Command> allCommands() {
  std::vector<Command> cmds;
#ifdef STSIM_HAVE_POOL_COMMAND
  cmds.push_back(poolCommand());
#endif
#ifdef STSIM_HAVE_ARM_COMMAND
  cmds.push_back(armCommand());
#endif
#ifdef STSIM_HAVE_HIGHWAY_COMMAND
  cmds.push_back(highwayCommand());
#endif
#ifdef STSIM_HAVE_BATCH_COMMAND
  cmds.push_back(batchCommand());
#endif
  return cmds;
}

}  // namespace st::cli

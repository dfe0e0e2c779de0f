// stsim: one front end, one subcommand per job.
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include <stsim/cli.hpp>
#include <stsim/commands.hpp>
#include <stsim/version.hpp>

namespace {

void printHelp(const std::vector<st::cli::Command>& cmds) {
  std::cout << "stsim: space-time simulation toolkit\n\n"
               "usage: stsim <command> [arguments] [options]\n"
               "       stsim <command> --help\n"
               "       stsim --version\n\ncommands:\n";
  for (const auto& c : cmds) std::cout << "  " << c.name << std::string(c.name.size() < 10 ? 10 - c.name.size() : 1, ' ') << c.summary << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  const auto cmds = st::cli::allCommands();
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0 ||
      std::strcmp(argv[1], "help") == 0) {
    printHelp(cmds);
    return argc < 2 ? 2 : 0;
  }
  if (std::strcmp(argv[1], "--version") == 0) {
    std::cout << "stsim " << STSIM_VERSION_STRING << "\n";
    return 0;
  }
  for (const auto& c : cmds) {
    if (c.name != argv[1]) continue;
    try {
      return c.run(argc - 2, argv + 2);
    } catch (const st::cli::UsageError& e) {
      std::cerr << "stsim " << c.name << ": " << e.what() << "\n";
      return 2;
    } catch (const std::exception& e) {
      // one line, whatever a library below put in the message (SUMO's span lines)
      std::string msg = e.what();
      for (char& ch : msg)
        if (ch == '\n' || ch == '\r') ch = ' ';
      std::cerr << "stsim " << c.name << ": error: " << msg << "\n";
      return 1;
    }
  }
  std::cerr << "stsim: unknown command '" << argv[1] << "' (see stsim --help)\n";
  return 2;
}

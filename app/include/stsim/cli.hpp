#pragma once
// A small command-line parser shared by the stsim subcommands: --name value, --name=value,
// flags, positionals. Unknown options and missing values raise UsageError (exit code 2).
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace st::cli {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  Args(std::string command, std::string synopsis) : command_(std::move(command)), synopsis_(std::move(synopsis)) {}

  // Declares an option taking a value; `meta` names the value in the help text.
  Args& option(const std::string& name, const std::string& meta, const std::string& help, std::string def = "");
  Args& flag(const std::string& name, const std::string& help);
  Args& positional(const std::string& name, const std::string& help, bool required = true);

  // Returns false if --help was given (help() should be printed and the command exit 0).
  bool parse(int argc, const char* const* argv);
  std::string help() const;

  bool has(const std::string& name) const;
  std::string get(const std::string& name) const;  // value or default
  double getDouble(const std::string& name) const;
  long getInt(const std::string& name) const;
  bool isSet(const std::string& name) const { return has(name); }
  const std::vector<std::string>& positionals() const { return positionalValues_; }
  std::optional<std::string> positionalValue(std::size_t i) const {
    return i < positionalValues_.size() ? std::optional<std::string>(positionalValues_[i]) : std::nullopt;
  }

 private:
  struct Opt {
    std::string meta, help, def;
    bool takesValue = true;
  };
  struct Pos {
    std::string name, help;
    bool required = true;
  };
  std::string command_, synopsis_;
  std::map<std::string, Opt> opts_;
  std::vector<std::string> order_;
  std::vector<Pos> pos_;
  std::map<std::string, std::string> values_;
  std::vector<std::string> positionalValues_;
};

}  // namespace st::cli

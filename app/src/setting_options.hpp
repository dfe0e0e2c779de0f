#pragma once
// The command line's half of a model's settings table (stio/settings_table.hpp): the options that
// stand for one key and --set KEY=VALUE[,...] become overrides the model's scenario reader checks
// as it checks the file's keys; a bad one is a usage error naming the option that gave it. Each
// command keeps its own way of naming an option in an error (`prefix`: "option " for stsim pool,
// "" for stsim arm), so its messages read alike.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <stio/settings_table.hpp>
#include <stsim/cli.hpp>

namespace st::cli {

// An option that stands for one key: {"df", "space.decomposition_factor"}.
struct KeyOption {
  const char* option;
  const char* key;
};

// The key's setting in the command's table, or null.
using FindSetting = std::function<const io::SettingSpec*(std::string_view key)>;

// The overrides of args: the key options given, then --set's. An unknown key or a key given twice
// throws UsageError ("--set x: unknown setting 'x' (stsim arm --settings lists them)").
std::vector<io::SettingOverride> settingOverrides(const Args& args, const std::vector<KeyOption>& options,
                                                  const FindSetting& find, const std::string& command,
                                                  const std::string& prefix);

// The usage error of an override the reader refused: "PREFIX--set KEY: PROBLEM", or the option
// that stands for the key.
[[noreturn]] void overrideError(const std::vector<io::SettingOverride>& overrides, const io::SettingError& e,
                                const std::string& prefix);

}  // namespace st::cli

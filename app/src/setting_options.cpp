#include "setting_options.hpp"

#include <set>
#include <stdexcept>

namespace st::cli {

std::vector<io::SettingOverride> settingOverrides(const Args& args, const std::vector<KeyOption>& options,
                                                  const FindSetting& find, const std::string& command,
                                                  const std::string& prefix) {
  std::vector<io::SettingOverride> out;
  std::set<std::string> given;
  auto add = [&](const std::string& key, const std::string& text, const std::string& option) {
    const io::SettingSpec* s = find(key);
    if (!s)
      throw UsageError(prefix + option + ": unknown setting '" + key + "' (stsim " + command + " --settings lists them)");
    // one key twice is a mistake to name, not to pass over: which value would count?
    if (!given.insert(s->key).second) throw UsageError(prefix + option + ": " + key + " given twice");
    out.push_back({s->key, text, option});
  };
  for (const KeyOption& o : options)
    if (args.has(o.option)) add(o.key, args.get(o.option), std::string("--") + o.option);
  if (!args.has("set")) return out;
  std::vector<io::Assignment> items;
  try {
    items = io::splitAssignments(args.get("set"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(prefix + "--set " + e.what());
  }
  for (const io::Assignment& a : items) add(a.key, a.text, "--set " + a.key);
  return out;
}

void overrideError(const std::vector<io::SettingOverride>& overrides, const io::SettingError& e, const std::string& prefix) {
  for (const io::SettingOverride& o : overrides)
    if (o.key == e.key()) throw UsageError(prefix + o.option + ": " + e.problem());
  throw UsageError(prefix + "--set " + e.key() + ": " + e.problem());
}

}  // namespace st::cli

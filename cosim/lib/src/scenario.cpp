#include <stcosim/scenario.hpp>
#include <stcosim/scenario_settings.hpp>

#include <yaml-cpp/yaml.h>

#include <sthighway/settings.hpp>
#include <sthighway/sumo_files.hpp>
#include <stio/input.hpp>
#include <stio/xml.hpp>
#include <stio/yaml.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string_view>

namespace st::cosim {
namespace {

namespace fs = std::filesystem;
namespace hw = st::highway;

// the largest SUMO input (route, additional file) read whole: bytes
constexpr std::size_t kMaxSumoInput = std::size_t{1} << 30;

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ',' || c == ' ') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

// Vehicle ids given twice in SUMO's route and additional files. SUMO stops on one with its own
// line, naming no file ("A vehicle with id 'v00' already exists.", or for flows "Another flow
// with the id 'f' exists."), and only when it reads the second, which may be minutes into the
// run; here it is named with file and line before SUMO starts. A vehicle and a trip share one
// id space, flows have their own. A scan of start tags, not a parser: SUMO's reader (and its
// XML errors) come after.
class RepeatedIds {
 public:
  void scan(const fs::path& file) {
    // bounded (a route file of a large demand runs to hundreds of MB, not for ever); a NUL byte is
    // left to the XML reader that follows, which names its line
    std::string text, error;
    if (!io::readFile(file, text, error, kMaxSumoInput)) throw ScenarioError(error);
    int line = 1;
    std::size_t counted = 0;
    for (std::size_t at = text.find('<'); at != std::string::npos; at = text.find('<', at + 1)) {
      if (text.compare(at, 4, "<!--") == 0) {
        at = text.find("-->", at);
        if (at == std::string::npos) break;
        continue;
      }
      std::size_t end = at + 1;
      while (end < text.size() && std::isalpha(static_cast<unsigned char>(text[end]))) ++end;
      const std::string tag = text.substr(at + 1, end - at - 1);
      if (tag != "vehicle" && tag != "trip" && tag != "flow") continue;
      const std::size_t close = text.find('>', end);
      const std::string id = attribute(text.substr(end, close == std::string::npos ? std::string::npos : close - end));
      if (id.empty()) continue;
      line += static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(counted),
                                          text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
      counted = at;
      auto& seen = tag == "flow" ? flows_ : vehicles_;
      const auto [it, fresh] = seen.emplace(id, Place{file, line});
      if (fresh) continue;
      const Place& first = it->second;
      const std::string where = first.file == file ? "line " + std::to_string(first.line)
                                                   : first.file.string() + ":" + std::to_string(first.line);
      throw ScenarioError(file.string() + ":" + std::to_string(line) + ": <" + tag + " id=\"" + id +
                          "\">: the id is given twice (first at " + where + "); SUMO would stop on it");
    }
  }

 private:
  struct Place {
    fs::path file;
    int line;
  };
  // the value of the attribute id in a start tag's text (after its name), "" if none
  static std::string attribute(const std::string& attrs) {
    for (std::size_t at = attrs.find("id"); at != std::string::npos; at = attrs.find("id", at + 1)) {
      if (at == 0 || !std::isspace(static_cast<unsigned char>(attrs[at - 1]))) continue;
      std::size_t k = at + 2;
      while (k < attrs.size() && std::isspace(static_cast<unsigned char>(attrs[k]))) ++k;
      if (k >= attrs.size() || attrs[k] != '=') continue;
      ++k;
      while (k < attrs.size() && std::isspace(static_cast<unsigned char>(attrs[k]))) ++k;
      if (k >= attrs.size() || (attrs[k] != '"' && attrs[k] != '\'')) continue;
      const std::size_t e = attrs.find(attrs[k], k + 1);
      if (e == std::string::npos) return "";
      return attrs.substr(k + 1, e - k - 1);
    }
    return "";
  }
  std::map<std::string, Place> vehicles_, flows_;
};

// The keys directly under a section of scenarioKeys() ("" for the top level).
std::set<std::string> keysUnder(const std::string& section) {
  const std::string prefix = section.empty() ? "" : section + ".";
  std::set<std::string> out;
  for (const std::string& k : scenarioKeys())
    if (k.compare(0, prefix.size(), prefix) == 0) out.insert(k.substr(prefix.size(), k.find('.', prefix.size()) - prefix.size()));
  return out;
}

// A YAML reader that names the file, line and key in every error (st::io words them).
class Reader {
 public:
  Reader(const fs::path& file) : y_(file.string()) {}

  [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& msg) const {
    y_.fail(n, key, msg);
  }
  [[noreturn]] void missing(const YAML::Node& n, const std::string& key, const std::string& hint) const {
    y_.missingKey(n, key, hint);
  }
  void checkKeys(const YAML::Node& map, const std::string& where, const std::set<std::string>& allowed) const {
    if (!map.IsMap())
      fail(map, where.empty() ? std::string("scenario") : where,
           where.empty() ? "must be a mapping of keys (at least sumocfg: FILE.sumocfg)" : "must be a mapping");
    y_.onlyKeys(map, where, [&](const std::string& k) { return allowed.count(k) > 0; });
  }
  double number(const YAML::Node& n, const std::string& key, double lo, double hi) const {
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n, key, "must be a number");
    }
    if (!std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream os;
      os << "must be in [" << lo << ", " << hi << "], got " << v;
      fail(n, key, os.str());
    }
    return v;
  }
  std::string text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail(n, key, "must be a string");
    return n.as<std::string>();
  }
  std::vector<std::string> list(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence()) fail(n, key, "must be a list");
    std::vector<std::string> out;
    for (const auto& e : n) out.push_back(text(e, key));
    return out;
  }
  YAML::Node load(const fs::path& path) const { return y_.load(path); }

 private:
  io::Yaml<ScenarioError> y_;
};

// SUMO 1.15's options that cannot work in a run stsim drives (embedded, or sumo-gui over TraCI):
// each with why, "" for any other argument. --remote-port made embedded SUMO wait for a client
// for ever, saying nothing.
std::string sumoArgumentProblem(const std::string& arg) {
  struct Refused {
    std::initializer_list<const char*> names;
    const char* why;
  };
  static const Refused refused[] = {
      {{"--remote-port", "--num-clients"},
       "makes SUMO wait for TraCI clients that never come (stsim drives SUMO itself; to attach to a SUMO you "
       "started, use --traci HOST:PORT)"},
      {{"-c", "--configuration-file"}, "is stsim's to give (the scenario's sumocfg)"},
      {{"-C", "--save-configuration", "--save-template", "-?", "--help", "-V", "--version"},
       "makes SUMO write or print and exit without running"},
      {{"-S", "--start", "-Q", "--quit-on-end"}, "is stsim's to give (with --gui it starts and ends sumo-gui)"},
      {{"-G", "--game", "--game.mode", "-D", "--demo"},
       "takes sumo-gui over (a game, or a demo that restarts for ever)"},
  };
  const std::string name = arg.substr(0, arg.find('='));
  for (const auto& r : refused)
    for (const char* n : r.names)
      if (name == n) return std::string("cannot work in a run stsim drives: it ") + r.why;
  return "";
}

constexpr double kBig = 1e12;
constexpr std::uint64_t kSumoDefaultSeed = 23423;  // SUMO's --seed default

// smart_types must name vTypes the run can have (a typo would equip nobody, silently): those of
// the sumocfg's route and additional files and SUMO's built-in defaults. Skipped when sumo_args
// loads further route or additional files, which may define more.
void checkSmartTypes(const Reader& r, const YAML::Node& node, const Scenario& s) {
  for (const auto& a : s.sumoArgs)
    if (a == "-r" || a == "-a" || a.rfind("--route-files", 0) == 0 || a.rfind("--additional-files", 0) == 0) return;
  std::set<std::string> known{"DEFAULT_VEHTYPE",  "DEFAULT_PEDTYPE", "DEFAULT_BIKETYPE",
                              "DEFAULT_TAXITYPE", "DEFAULT_RAILTYPE", "DEFAULT_CONTAINERTYPE"};
  std::set<std::string> defined;
  const SumoConfigFiles files = checkSumoConfig(s.sumocfg);
  std::vector<fs::path> sources = files.routes;
  sources.insert(sources.end(), files.additionals.begin(), files.additionals.end());
  for (const auto& f : sources)
    for (const auto& [id, info] : hw::readSumoVehicleTypes(f)) defined.insert(id);
  known.insert(defined.begin(), defined.end());
  std::size_t i = 0;
  for (const auto& e : node) {
    const std::string t = e.as<std::string>();
    if (!known.count(t)) {
      std::string list;
      for (const auto& d : defined) list.append(list.empty() ? "" : ", ").append(d);
      r.fail(e, "smart_types[" + std::to_string(i) + "]",
             "unknown vType '" + t + "' (" + s.sumocfg.filename().string() + "'s files define: " +
                 (list.empty() ? std::string("none") : list) + ")");
    }
    ++i;
  }
}

// The node of a nested key ("safe_time.brake_force.truck") in a mapping; undefined if absent.
// Through const nodes only: a mutable yaml-cpp node would add the keys it is asked for.
YAML::Node settingNode(const YAML::Node& map, std::string_view key) {
  if (!map || !map.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  const auto dot = key.find('.');
  const YAML::Node child = map[std::string(key.substr(0, dot))];
  if (dot == std::string_view::npos) return child;
  return settingNode(child, key.substr(dot + 1));
}

// A YAML scalar as s's type: yaml-cpp's reading (1e3, yes/no as booleans) or, for a number key,
// its word; a value of another type is worded as on the command line ("must be a number, got 'x'").
io::SettingValue yamlValue(const YAML::Node& n, const io::SettingSpec& s) {
  try {
    switch (s.type) {
      case io::SettingType::Number:
      case io::SettingType::Integer:
        if (*s.words && n.Scalar() == s.words) return n.Scalar();
        return n.as<double>();
      case io::SettingType::Boolean: return n.as<bool>();
      case io::SettingType::Choice: return n.as<std::string>();
    }
  } catch (const YAML::Exception&) {
  }
  return io::settingValue(s, n.Scalar());  // throws SettingError, as for the same text on the command line
}

// Every key of a table the YAML gives, checked and stored, then what no single key can check;
// each error names the file, line and key.
template <class Config>
void readSettings(const Reader& r, const YAML::Node& root, std::span<const io::Setting<Config>> table, Config& c,
                  void (*checkAll)(const Config&)) {
  for (const io::Setting<Config>& setting : table) {
    const YAML::Node n = settingNode(root, setting.key);
    if (!n) continue;
    if (!n.IsScalar()) r.fail(n, setting.key, "must be " + io::expected(setting));
    try {
      io::applySetting(c, setting, yamlValue(n, setting));
    } catch (const io::SettingError& e) {
      r.fail(n, e.key(), e.problem());
    }
  }
  try {
    checkAll(c);
  } catch (const io::SettingError& e) {
    // the key if given, else its section ("brake": the default it is measured against), else the file
    const YAML::Node n = settingNode(root, e.key());
    const YAML::Node section = settingNode(root, io::keySection(e.key()));
    r.fail(n ? n : section ? section : root, e.key(), e.problem());
  }
}

void readYaml(const fs::path& path, Scenario& s) {
  const Reader r(path);
  const YAML::Node root = r.load(path);
  r.checkKeys(root, "", keysUnder(""));
  if (!root["sumocfg"]) r.missing(root, "sumocfg", "the SUMO configuration to run");
  s.sumocfg = path.parent_path() / r.text(root["sumocfg"], "sumocfg");
  if (auto n = root["smart_types"]) s.plugin.smart.types = r.list(n, "smart_types");
  if (const YAML::Node b = root["brake"]) {
    if (auto n = b["duration"])  // an early version's key: say what replaced it rather than "unknown"
      r.fail(n, "brake.duration", "no longer used: a braking car slows to its foe's speed (see brake.deceleration)");
  }
  // the scenario's settings and the monitor's: a table each (stcosim/scenario_settings.hpp,
  // sthighway/settings.hpp) names, checks and words them
  for (const char* section : {"brake", "safe_time", "safe_time.brake_force", "conflict", "concentric", "cells", "hindsight"})
    if (const YAML::Node node = settingNode(root, section)) r.checkKeys(node, section, keysUnder(section));
  readSettings(r, root, scenarioSettings(), s, checkScenarioSettings);
  readSettings(r, root, hw::monitorSettings(), s.plugin.monitor, hw::checkSettings);
  if (auto list = root["incidents"]) {
    if (!list.IsSequence()) r.fail(list, "incidents", "must be a list of {time, near: [x, y], speed, deceleration, hold}");
    int i = 0;
    for (const auto& e : list) {
      const std::string where = "incidents[" + std::to_string(i++) + "]";
      r.checkKeys(e, where, {"time", "near", "speed", "deceleration", "hold"});
      Incident inc;
      if (!e["time"]) r.missing(e, where + ".time", "when the vehicle starts braking, s");
      inc.time = r.number(e["time"], where + ".time", 0, kBig);
      const YAML::Node near = e["near"];
      if (!near || !near.IsSequence() || near.size() != 2)
        r.fail(near ? near : e, where + ".near", "must be [x, y]: the vehicle nearest to this point brakes");
      inc.x = r.number(near[0], where + ".near", -kBig, kBig);
      inc.y = r.number(near[1], where + ".near", -kBig, kBig);
      if (auto n = e["speed"]) inc.speed = r.number(n, where + ".speed", 0, 200);
      if (auto n = e["deceleration"]) inc.deceleration = r.number(n, where + ".deceleration", 0.1, 50);
      if (auto n = e["hold"]) inc.hold = r.number(n, where + ".hold", 0, kBig);
      s.plugin.incidents.push_back(inc);
    }
  }
  if (auto n = root["sumo_args"]) {
    s.sumoArgs = r.list(n, "sumo_args");
    for (std::size_t i = 0; i < s.sumoArgs.size(); ++i)
      if (const std::string why = sumoArgumentProblem(s.sumoArgs[i]); !why.empty())
        r.fail(n[i], "sumo_args", s.sumoArgs[i] + " " + why);
  }
  if (auto n = root["out"]) s.out = fs::path(r.text(n, "out"));
  s.plugin.smart.seed = s.seed;
  // last, so a scenario's other mistakes are named first: the file it runs must be there
  {
    std::error_code ec;
    const auto st = fs::status(s.sumocfg, ec);
    if (!fs::exists(st)) r.fail(root["sumocfg"], "sumocfg", "no such file: " + s.sumocfg.string());
    if (fs::is_directory(st)) r.fail(root["sumocfg"], "sumocfg", "is a directory, not a .sumocfg: " + s.sumocfg.string());
    if (const std::string why = io::notReadableReason(s.sumocfg); !why.empty()) r.fail(root["sumocfg"], "sumocfg", why);
  }
  if (auto n = root["smart_types"]) checkSmartTypes(r, n, s);
}

}  // namespace

const std::vector<std::string>& scenarioKeys() {
  static const std::vector<std::string> keys = [] {
    // the paths and lists only the YAML reader reads, then the two tables' keys
    std::vector<std::string> k = {"sumocfg", "description", "smart_types", "incidents", "sumo_args", "out"};
    for (const ScenarioSetting& setting : scenarioSettings()) k.push_back(setting.key);
    for (const hw::Setting& setting : hw::monitorSettings()) k.push_back(setting.key);
    return k;
  }();
  return keys;
}

namespace {

// A SUMO configuration's options: <configuration><SECTION><KEY value="..."/>, in the file's
// order. Malformed XML throws "file:line: ..." (io's XML reader).
struct SumoOptions {
  struct Option {
    std::string section, key, value;
  };
  bool configuration = false;  // its root is <configuration>
  std::vector<Option> options;
  // the first value of key, in the given section or ("") in any
  const std::string* value(std::string_view section, std::string_view key) const {
    for (const Option& o : options)
      if (o.key == key && (section.empty() || o.section == section)) return &o.value;
    return nullptr;
  }
};

SumoOptions readSumoOptions(std::string text, const fs::path& file) {
  io::XmlScanner x(std::move(text), file.string(), io::raiseAs<ScenarioError>);
  x.requireBalanced();
  SumoOptions out;
  io::XmlScanner::Tag t;
  bool root = true;
  while (x.next(t)) {
    if (root) out.configuration = !t.closing && t.name == "configuration";
    root = false;
    if (!out.configuration || t.closing || x.depth() != 2) continue;
    if (const std::string* v = t.attr("value")) out.options.push_back({x.openElement(1), t.name, *v});
  }
  return out;
}

// text that is a whole number in [0, 2^64) and nothing else
bool wholeNumber(const std::string& text, std::uint64_t& n) {
  const char* end = text.data() + text.size();
  const auto [at, ec] = std::from_chars(text.data(), end, n);
  return ec == std::errc() && at == end && !text.empty();
}

}  // namespace

Scenario loadScenario(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw ScenarioError(path.string() + ": " + (ec ? ec.message() : "no such file"));
  Scenario s;
  s.source = path;
  const std::string ext = path.extension().string();
  if (ext == ".yaml" || ext == ".yml") {
    readYaml(path, s);
  } else if (ext == ".sumocfg" || ext == ".xml") {
    s.sumocfg = path;
    // a plain SUMO config runs as it says: its seed (or SUMO's own), the smart-car draw with it;
    // its outputs in out/<config name>/ (not beside whatever the current folder holds)
    s.passSeed = false;
    s.seed = kSumoDefaultSeed;
    try {
      std::string text, error;
      if (io::readTextFile(path, text, error)) {
        const SumoOptions options = readSumoOptions(std::move(text), path);
        std::uint64_t seed = 0;
        if (const std::string* v = options.value("random_number", "seed"); v && wholeNumber(*v, seed)) s.seed = seed;
      }
    } catch (const std::exception&) {
      // reported with its file name by checkSumoConfig
    }
    s.plugin.smart.seed = s.seed;
    s.out = fs::path("out") / path.stem();
  } else {
    throw ScenarioError(path.string() + ": expected a scenario .yaml or a SUMO .sumocfg");
  }
  return s;
}

// The name of an XML file's root element: the first start tag past the declaration, comments
// and DOCTYPE in its first 64 KiB ("" if none there).
std::string rootElement(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string head(65536, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  for (std::size_t at = head.find('<'); at != std::string::npos; at = head.find('<', at + 1)) {
    if (head.compare(at, 4, "<!--") == 0) {
      at = head.find("-->", at);
      if (at == std::string::npos) return "";
      continue;
    }
    if (head.compare(at, 2, "<?") == 0 || head.compare(at, 2, "<!") == 0) continue;
    std::size_t end = at + 1;
    while (end < head.size() && (std::isalnum(static_cast<unsigned char>(head[end])) || head[end] == '_' || head[end] == '-'))
      ++end;
    return head.substr(at + 1, end - at - 1);
  }
  return "";
}

SumoConfigFiles checkSumoConfig(const fs::path& sumocfg) {
  std::error_code ec;
  const fs::file_status st = fs::status(sumocfg, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) throw ScenarioError(sumocfg.string() + ": " + ec.message());
  if (!fs::exists(st)) throw ScenarioError(sumocfg.string() + ": no such SUMO configuration file");
  if (fs::is_directory(st)) throw ScenarioError(sumocfg.string() + ": is a directory, not a SUMO configuration file");
  // read bounded first: /dev/zero read for ever (2.4 GB in 5 s) in Boost's reader
  std::string text, error;
  if (!io::readTextFile(sumocfg, text, error)) throw ScenarioError(error);
  const SumoOptions options = readSumoOptions(std::move(text), sumocfg);
  if (!options.configuration) throw ScenarioError(sumocfg.string() + ": not a SUMO configuration (no <configuration>)");
  const fs::path dir = sumocfg.parent_path();
  SumoConfigFiles out;
  auto value = [&](const std::string& key) -> std::optional<std::string> {
    // options may sit in any section (<input>, <time>, ...)
    if (const std::string* v = options.value({}, key)) return *v;
    return std::nullopt;
  };
  auto resolve = [&](const std::string& key, const std::string& f) {
    const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : dir / f;
    std::error_code why;
    const bool there = fs::exists(p, why);
    if (why)  // a name too long, a folder we may not enter: not "does not exist", and no filesystem_error
      throw ScenarioError(sumocfg.string() + ": " + key + " '" + p.string() + "': " + why.message());
    if (!there) throw ScenarioError(sumocfg.string() + ": " + key + " '" + p.string() + "' does not exist");
    if (const std::string bad = io::notReadableReason(p); !bad.empty())
      throw ScenarioError(sumocfg.string() + ": " + key + ": " + bad);
    return p;
  };
  const auto net = value("net-file");
  if (!net) throw ScenarioError(sumocfg.string() + ": names no net-file");
  out.net = resolve("net-file", *net);
  if (auto r = value("route-files"))
    for (const auto& f : splitList(*r)) out.routes.push_back(resolve("route-files", f));
  if (auto a = value("additional-files"))
    for (const auto& f : splitList(*a)) out.additionals.push_back(resolve("additional-files", f));
  // a configuration or a network named as routes: SUMO reads no vehicle from it and says nothing.
  // A configuration is any <...configuration> root (SUMO's tools write <sumoConfiguration>,
  // <duarouterConfiguration>, ...), and a .sumocfg that is neither routes nor additionals
  auto isConfiguration = [](const fs::path& f, const std::string& root) {
    std::string lower = root;
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const std::string config = "configuration";
    if (lower.size() >= config.size() && lower.compare(lower.size() - config.size(), config.size(), config) == 0)
      return true;
    return f.extension() == ".sumocfg" && !root.empty() && root != "routes" && root != "additional";
  };
  for (const auto& [key, files] : {std::pair{"route-files", &out.routes}, std::pair{"additional-files", &out.additionals}})
    for (const fs::path& f : *files) {
      const std::string root = rootElement(f);
      if (root == "net" || isConfiguration(f, root))
        throw ScenarioError(sumocfg.string() + ": " + key + " '" + f.string() + "' is a SUMO " +
                            (root == "net" ? "network" : "configuration") + ", not " +
                            (std::string(key) == "route-files" ? "a route" : "an additional") + " file");
    }
  try {
    if (auto v = value("step-length")) out.stepLength = std::stod(*v);
    if (auto v = value("end")) out.end = std::stod(*v);
  } catch (const std::exception&) {
    throw ScenarioError(sumocfg.string() + ": step-length and end must be numbers of seconds");
  }
  // what SUMO would stop on naming no file: a vehicle id given twice; a vType's mass param that
  // is not a positive number (SUMO keeps params as text; stsim met NaN when the vehicle departed)
  std::vector<fs::path> inputs = out.routes;
  inputs.insert(inputs.end(), out.additionals.begin(), out.additionals.end());
  RepeatedIds ids;
  for (const fs::path& f : inputs) {
    ids.scan(f);
    try {
      hw::readSumoVehicleTypes(f);
    } catch (const hw::InputError& e) {
      throw ScenarioError(e.what());
    }
  }
  return out;
}

std::vector<std::string> sumoArguments(const Scenario& s) {
  std::vector<std::string> a{"-c", s.sumocfg.string()};
  if (s.passSeed) a.insert(a.end(), {"--seed", std::to_string(s.seed)});
  a.insert(a.end(), {"--collision.action", s.collisionAction, "--no-step-log", "true", "--duration-log.disable", "true",
                     "--duration-log.statistics", "false", "--no-warnings", "true"});
  auto option = [&](const char* name, double value) {
    std::ostringstream os;
    os.precision(17);  // round-trips the double
    os << value;
    a.push_back(name);
    a.push_back(os.str());
  };
  if (s.end) option("--end", *s.end);
  if (s.demandScale) option("--scale", *s.demandScale);
  if (s.collisionMinGapFactor) option("--collision.mingap-factor", *s.collisionMinGapFactor);
  a.insert(a.end(), s.sumoArgs.begin(), s.sumoArgs.end());
  return a;
}

}  // namespace st::cosim

#include <stsim/cli.hpp>

#include <cmath>
#include <sstream>

namespace st::cli {

Args& Args::option(const std::string& name, const std::string& meta, const std::string& help, std::string def) {
  opts_[name] = Opt{meta, help, std::move(def), true};
  order_.push_back(name);
  return *this;
}

Args& Args::flag(const std::string& name, const std::string& help) {
  opts_[name] = Opt{"", help, "", false};
  order_.push_back(name);
  return *this;
}

Args& Args::positional(const std::string& name, const std::string& help, bool required) {
  pos_.push_back(Pos{name, help, required});
  return *this;
}

bool Args::parse(int argc, const char* const* argv) {
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--help" || a == "-h") return false;
    if (a.rfind("--", 0) == 0 && a.size() > 2) {
      std::string name = a.substr(2), value;
      bool inlineValue = false;
      if (auto eq = name.find('='); eq != std::string::npos) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
        inlineValue = true;
      }
      auto it = opts_.find(name);
      if (it == opts_.end()) throw UsageError("unknown option --" + name + " (see stsim " + command_ + " --help)");
      if (it->second.takesValue) {
        if (!inlineValue) {
          if (i + 1 >= argc) throw UsageError("option --" + name + " needs a value <" + it->second.meta + ">");
          value = argv[++i];
        }
      } else if (inlineValue) {
        throw UsageError("option --" + name + " takes no value");
      }
      values_[name] = value;
      continue;
    }
    if (a.size() > 1 && a[0] == '-' && !(std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.'))
      throw UsageError("unknown option " + a + " (see stsim " + command_ + " --help)");
    positionalValues_.push_back(a);
  }
  std::size_t required = 0;
  for (const auto& p : pos_) required += p.required ? 1 : 0;
  if (positionalValues_.size() < required)
    throw UsageError("missing argument " + pos_[positionalValues_.size()].name + " (see stsim " + command_ + " --help)");
  if (positionalValues_.size() > pos_.size())
    throw UsageError("unexpected argument '" + positionalValues_[pos_.size()] + "' (see stsim " + command_ + " --help)");
  return true;
}

std::string Args::help() const {
  std::ostringstream os;
  os << "usage: stsim " << command_;
  for (const auto& p : pos_) os << (p.required ? " " : " [") << p.name << (p.required ? "" : "]");
  os << " [options]\n\n" << synopsis_ << "\n";
  if (!pos_.empty()) {
    os << "\narguments:\n";
    for (const auto& p : pos_) os << "  " << p.name << "\n      " << p.help << "\n";
  }
  os << "\noptions:\n";
  for (const auto& name : order_) {
    const Opt& o = opts_.at(name);
    os << "  --" << name << (o.takesValue ? " <" + o.meta + ">" : "") << "\n      " << o.help;
    if (!o.def.empty()) os << " (default: " << o.def << ")";
    os << "\n";
  }
  os << "  --help\n      show this help\n";
  return os.str();
}

bool Args::has(const std::string& name) const { return values_.count(name) > 0; }

std::string Args::get(const std::string& name) const {
  if (auto it = values_.find(name); it != values_.end()) return it->second;
  auto o = opts_.find(name);
  return o == opts_.end() ? std::string() : o->second.def;
}

double Args::getDouble(const std::string& name) const {
  const std::string s = get(name);
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (...) {
    used = 0;
  }
  if (used != s.size() || s.empty() || !std::isfinite(v))
    throw UsageError("option --" + name + " needs a finite number, got '" + s + "'");
  return v;
}

long Args::getInt(const std::string& name) const {
  const std::string s = get(name);
  std::size_t used = 0;
  long v = 0;
  try {
    v = std::stol(s, &used);
  } catch (...) {
    used = 0;
  }
  if (used != s.size() || s.empty()) throw UsageError("option --" + name + " needs an integer, got '" + s + "'");
  return v;
}

}  // namespace st::cli

// stsim pool: plays a pool scenario (the report's OOSPG, §2) and writes its record; or runs the
// report's Fig. 13 study.
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <stsim/cli.hpp>
#include <stsim/commands.hpp>

#include <stpool/game.hpp>
#include <stpool/report.hpp>
#include <stpool/scenario.hpp>
#include <stpool/settings.hpp>
#include <stpool/study.hpp>
#include <stio/format.hpp>
#include <stio/input.hpp>
#include <stio/output.hpp>
#include <stio/settings_table.hpp>

#include "setting_options.hpp"
#include "stop_signals.hpp"
#ifdef STSIM_HAVE_POOL_SERVE
#include <boost/asio/io_context.hpp>
#include <stio/data_file.hpp>
#include <stnet/frame.hpp>

#include "pool_server.hpp"
#endif

namespace st::cli {

namespace {

// Events a run records unless --max-events says otherwise: 135 bytes a row, about 27 MB of
// events.csv (and 7 MB of animation.html); box100's 10 s make 13 600.
constexpr std::size_t kDefaultMaxEvents = 200'000;
constexpr std::size_t kMaxPage = 16u << 20;  // bytes: the shipped page is 60 KB

// The settings a command line gives (stpool/settings.hpp): --set KEY=VALUE[,...] and the options
// that stand for one key (--space: space.kind, --df: space.decomposition_factor), checked by the
// table when the scenario is read, over the file's values.
std::vector<pool::SettingOverride> settingOverrides(const Args& args) {
  return cli::settingOverrides(args, {{"space", "space.kind"}, {"df", "space.decomposition_factor"}},
                               [](std::string_view key) -> const io::SettingSpec* { return pool::findSetting(key); },
                               "pool", "option ");
}

// A scenario with the command line's settings over its own: a bad value names its option.
pool::Scenario loadWithSettings(const std::string& path, const std::vector<pool::SettingOverride>& overrides) {
  try {
    return pool::loadScenario(path, overrides);
  } catch (const pool::SettingError& e) {
    overrideError(overrides, e, "option ");
  }
}

void printSummary(std::ostream& os, const pool::RunRecord& run, const pool::Game& game) {
  const auto& c = game.simulator().counters();
  os << "stsim pool: " << io::printable(run.scenario) << ": " << game.specs().size() << " balls, space " << run.spaceDescription
     << "\n";
  os << std::setprecision(4);
  for (const auto& s : run.shots) {
    os << "  shot " << s.index + 1;
    if (s.ball >= 0) os << " (ball " << s.ball << ")";
    else os << " (no strike)";
    os << ": " << s.events << " events, ends by " << pool::toString(s.ending) << " at " << s.end << " s\n";
  }
  const auto counts = pool::eventCounts(run.events);
  os << "  events:";
  for (int k = 0; k < static_cast<int>(pool::PoolEventKind::Count); ++k)
    os << " " << pool::toString(static_cast<pool::PoolEventKind>(k)) << " " << counts[k];
  os << "\n  pocketed:";
  if (game.pocketed().empty()) os << " none";
  for (const auto& p : game.pocketed()) os << " " << p.number << "@" << p.t << "s";
  os << "\n";
  const std::uint64_t ev = c.totalEvents();
  os << "  collision checks " << c.pairChecks << " (" << (ev ? static_cast<double>(c.pairChecks) / static_cast<double>(ev) : 0.0)
     << " per event)";
  if (!run.shots.empty()) {
    double drift = 0.0;
    for (const auto& s : run.shots) drift = std::max(drift, std::abs(s.energyDrift()));
    os << ", kinetic energy " << run.shots.front().keStart << " J -> " << run.shots.back().keEnd << " J on the table";
    if (game.friction() > 0.0) os << " (friction " << game.friction() << " m/s^2)";
    else os << ", max energy drift " << drift;
  }
  os << "\n  wall time " << run.wallSeconds << " s\n";
}


#ifdef STSIM_HAVE_POOL_SERVE

int runServe(int argc, const char* const* argv) {
  Args args("pool serve",
            "The report's interactive table in the browser: serves one page and a WebSocket per tab, each\n"
            "tab its own game; the server plays every shot with stcore and streams its events, the page\n"
            "animates them. Open the printed address. Protocol and bounds in models/pool/README.md.");
  args.positional("SCENARIO.yaml", "the game's initial layout and settings (default: the standard rack)", false)
      .option("listen", "HOST:PORT", "address to listen on (port 0: pick one and print it)", "127.0.0.1:8080")
      .option("max-games", "N", "games (tabs) served at once; more are refused", "64")
      .option("page", "FILE", "serve this page instead of the installed one (for working on it)");
  if (!args.parse(argc, argv)) {
    std::cout << args.help();
    return 0;
  }
  const auto hp = net::parseHostPort(args.get("listen"));
  if (!hp) throw UsageError("option --listen: expected HOST:PORT, got '" + args.get("listen") + "'");
  const long maxGames = args.getInt("max-games");
  if (maxGames < 1 || maxGames > 10000) throw UsageError("option --max-games needs an integer in 1..10000");
  const pool::Scenario scenario = args.positionalValue(0) ? pool::loadScenario(*args.positionalValue(0))
                                                          : pool::parseScenario(pool::kServeDefaultScenario, "(default rack)");
  pool::ServeConfig cfg = pool::defaultServeConfig();
  cfg.web.net.address = hp->host == "localhost" ? "127.0.0.1" : hp->host;
  cfg.web.net.port = hp->port;
  cfg.web.net.maxConnections = static_cast<std::size_t>(maxGames);
  const std::filesystem::path page =
      args.has("page") ? std::filesystem::path(args.get("page")) : io::dataFile("pool/index.html", STSIM_POOL_PAGE);
  // bounded (--page /dev/zero read 2.4 GB in 5 s); an empty page is a mistake, not a game
  std::string why;
  if (!io::readTextFile(page, cfg.page, why, kMaxPage)) throw std::runtime_error(why);
  if (cfg.page.find_first_not_of(" \t\r\n") == std::string::npos)
    throw std::runtime_error(page.string() + ": the page is empty");
  boost::asio::io_context io;
  pool::PoolServer server(io, scenario, cfg);
  std::cout << "pool serve: http://" << cfg.web.net.address << ":" << server.port() << "/ (" << io::printable(scenario.name)
            << ", at most " << maxGames << " games; Ctrl-C stops)" << std::endl;
  const int sig = server.run();
  const auto& c = server.counters();
  std::cout << "pool serve: " << (sig ? StopSignals::name(sig) : "stopped") << ", " << c.games
            << " games, " << c.shots << " shots, " << c.messages << " messages, " << c.errors << " refused" << std::endl;
  return sig ? 128 + sig : 0;  // 130, 143, 129: as every command (stop_signals.hpp)
}
#endif

// events.csv (and animation.html) grow with the events: a runaway time limit (until 1e12 on
// box100) wrote 269 MB before the library's own bound stopped it
std::size_t maxEventsOption(const Args& args) {
  if (!args.has("max-events")) return kDefaultMaxEvents;
  const long n = args.getInt("max-events");
  if (n < 1 || static_cast<std::size_t>(n) > pool::kMaxEvents)
    throw UsageError("option --max-events: expected 1.." + std::to_string(pool::kMaxEvents) + ", got " +
                     args.get("max-events"));
  return static_cast<std::size_t>(n);
}

// --until: every shot's time limit (its own too), checked as the key until; -1: none given
double untilOption(const Args& args) {
  if (!args.has("until")) return -1.0;
  try {
    return std::get<double>(io::settingValue(*pool::findSetting("until"), args.get("until")));
  } catch (const pool::SettingError& e) {
    throw UsageError("option --until: " + e.problem());
  }
}

// stsim pool's options
Args poolArgs() {
  Args args("pool",
            "Plays a pool scenario on the event-driven simulator (the report's OOSPG) and writes\n"
            "events.csv, summary.json, table.svg and animation.html to --out; or, with --study fig13,\n"
            "prints the report's Fig. 13 collision-check study and its extension to large boxes.\n"
            "  stsim pool serve [SCENARIO.yaml] --listen 127.0.0.1:8080   play it in the browser (pool serve --help)");
  args.positional("SCENARIO.yaml", "the scenario (models/pool/README.md documents its keys)", false)
      .option("out", "DIR", "write the run's files to this directory (created if missing); with --study, fig13.txt")
      .option("space", "KIND", "override space.kind: " + pool::expected(*pool::findSetting("space.kind")))
      .option("df", "N|auto", "override space.decomposition_factor (quadtree only): " +
                                  pool::valuesText(*pool::findSetting("space.decomposition_factor")))
      .option("until", "T", "override every shot's time limit (s), checked as the key until")
      .option("set", "KEY=VALUE,...", "settings over the scenario's, e.g. space.cell_size=0.2 (checked as in the YAML;\n"
                                      "--settings lists them)")
      .flag("settings", "print every setting (key, range, default, what it sets) and exit; with SCENARIO and\n"
                        "--set, --space, --df, the values in effect")
      .option("max-events", "N", "stop the run after N events, an error naming events.csv (default 200000, about\n"
                                 "27 MB of events.csv; at most 2000000)")
      .option("study", "NAME", "run a study instead of a scenario: fig13")
      .option("counting", "HOW", "with --study fig13: events (the simulator's own checks, the default) or report\n"
                                 "(the report's per-step counting as well, side by side)");
  return args;
}

// --settings: the table, with the defaults or the values in effect
int printSettings(const Args& args) {
  const std::vector<pool::SettingOverride> overrides = settingOverrides(args);
  if (!args.positionalValue(0)) {
    if (!overrides.empty()) throw UsageError("--settings: option " + overrides.front().option + " needs a SCENARIO");
    std::cout << pool::settingsReferenceMarkdown();
    return 0;
  }
  const pool::Scenario sc = loadWithSettings(*args.positionalValue(0), overrides);
  std::cout << pool::settingsReferenceMarkdown(&sc, "in effect");
  return 0;
}

// --study fig13: the report's collision-check study
int runStudy(const Args& args) {
  if (args.get("study") != "fig13") throw UsageError("unknown study '" + args.get("study") + "' (fig13)");
  if (args.positionalValue(0)) throw UsageError("--study takes no scenario file");
  pool::Counting counting = pool::Counting::Events;
  if (args.has("counting")) {
    if (args.get("counting") == "report") counting = pool::Counting::Report;
    else if (args.get("counting") != "events")
      throw UsageError("option --counting: unknown counting '" + args.get("counting") + "' (events, report)");
  }
  if (!args.has("out")) {
    pool::printFig13Study(std::cout, counting);
    return 0;
  }
  // the folder first: a minute of study is not run for a folder that cannot be made
  const std::filesystem::path dir = args.get("out");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create the folder: " + ec.message());
  std::ostringstream study;
  pool::printFig13Study(study, counting);
  io::writeTextFile(dir / "fig13.txt", study.str());
  std::cout << study.str() << "  wrote fig13.txt to " << dir.string() << "\n";
  return 0;
}

int runPool(int argc, const char* const* argv) {
#ifdef STSIM_HAVE_POOL_SERVE
  if (argc > 0 && std::string(argv[0]) == "serve") return runServe(argc - 1, argv + 1);
#endif
  Args args = poolArgs();
  if (!args.parse(argc, argv)) {
    std::cout << args.help();
    return 0;
  }
  if (args.has("settings")) return printSettings(args);
  if (args.has("counting") && !args.has("study")) throw UsageError("option --counting needs --study fig13");
  if (args.has("study")) return runStudy(args);
  const auto path = args.positionalValue(0);
  if (!path) throw UsageError("missing argument SCENARIO.yaml (see stsim pool --help)");

  // the overrides are checked by the settings table as their YAML keys are, the problem named at
  // the option: `--space cells --df 7` is refused as `kind: cells` with a decomposition_factor is.
  // --space sets the file's keys of its old kind aside.
  const pool::Scenario scenario = loadWithSettings(*path, settingOverrides(args));
  const double until = untilOption(args);

  const std::size_t maxEvents = maxEventsOption(args);

  pool::Game game(scenario, pool::simulatorConfig(scenario));
  // Ctrl-C, SIGTERM, SIGHUP: stop at the next event and write what was played (never a cut row)
  const StopSignals stopSignals;
  pool::RunRecord run = pool::playScenario(game, scenario, until, StopSignals::requested, maxEvents);
  const int stopSignal = StopSignals::signal();
  if (run.eventLimitReached) {
    // the file the limit protects, the limit and how to change it; the rows so far are written
    const std::string where =
        args.has("out") ? (std::filesystem::path(args.get("out")) / "events.csv").string() : *path;
    run.error = where + ": stopped at the limit of " + std::to_string(maxEvents) + " events at t = " +
                io::number(run.events.empty() ? 0.0 : run.events.back().t, 6) +
                " s; raise --max-events (at most " + std::to_string(pool::kMaxEvents) +
                ") or lower until (or --until)";
  }
  if (run.error.empty() && stopSignal) run.error = "interrupted while writing";

  // the record is written even when the run stopped on an error
  if (args.has("out")) {
    const std::filesystem::path dir = args.get("out");
    std::filesystem::create_directories(dir);
    // on a full disk: events.csv trimmed to its whole rows, the summary saying so (or none, never
    // a cut one), and the error names the first file that failed (st::io's writers)
    std::string failed;
    try {
      io::writeRowsFile(dir / "events.csv", [&](std::ostream& os) { pool::writeEventsCsv(os, run, game); });
    } catch (const std::runtime_error& e) {
      failed = e.what();
      run.error = run.error.empty() ? failed : run.error + "; " + failed;
    }
    try {
      io::writeTextFile(dir / "summary.json", [&](std::ostream& os) { pool::writeSummaryJson(os, run, game); });
    } catch (const std::runtime_error& e) {
      if (failed.empty()) throw;
    }
    if (!failed.empty()) throw std::runtime_error(failed);
    io::writeTextFile(dir / "table.svg", [&](std::ostream& os) { pool::writeTableSvg(os, game, run.scenario); });
    io::writeTextFile(dir / "animation.html", [&](std::ostream& os) { pool::writeAnimationHtml(os, run, game); });
  }
  printSummary(std::cout, run, game);
  if (args.has("out")) std::cout << "  wrote events.csv, summary.json, table.svg, animation.html to " << args.get("out") << "\n";
  std::cout.flush();
  if (stopSignal) {
    std::cerr << "stsim pool: " << run.error << "; results so far written\n";
    return StopSignals::exitCode();
  }
  if (!run.error.empty()) throw std::runtime_error(run.error);
  return 0;
}

}  // namespace

Command poolCommand() {
  return Command{"pool", "play a pool scenario (the report's OOSPG) or run its Fig. 13 study", runPool};
}

}  // namespace st::cli

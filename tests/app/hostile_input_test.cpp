// Hostile input to the front end, end to end: whole-file reads are bounded (a device, a
// FIFO, a directory or an empty page is one line naming it, exit 1, at once), values no input has
// are named by their key, outputs stay valid UTF-8 and a failed map fails the run.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include "cosim/test_util.hpp"

#include <stio/format.hpp>

namespace {

namespace fs = std::filesystem;
using st::cosim::test::freshDir;
using st::cosim::test::slurp;
using st::cosim::test::StsimProcess;

const fs::path kSource = STSIM_SOURCE_DIR;
const fs::path kLanedrop = kSource / "tests/data/highway";

// stsim's exit code, or -1 if it ran past `seconds` (killed: it read for ever)
// {"--bash-c", CMD, ARGS...} runs `bash -c CMD` with stsim as $1 and ARGS after it (a ulimit first).
int runWithin(const std::vector<std::string>& args, const fs::path& dir, std::string& err, double seconds = 10) {
  const bool shell = !args.empty() && args[0] == "--bash-c";
  StsimProcess p(shell ? std::vector<std::string>(args.begin() + 2, args.end()) : args, dir,
                 shell ? std::vector<std::string>{"bash", "-c", args.at(1), "bash"} : std::vector<std::string>{});
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (p.running()) {
    if (std::chrono::steady_clock::now() > until) {
      p.signal(SIGKILL);
      p.wait();
      err = p.err();
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  err = p.err();
  return p.wait();
}

TEST(HostileInput, PoolServePageMustBeAPageFile) {
  const fs::path dir = freshDir("serve_page");
  ASSERT_EQ(::mkfifo((dir / "fifo.html").c_str(), 0644), 0);
  fs::create_directories(dir / "folder");
  std::ofstream(dir / "empty.html") << "\n  \n";
  const std::pair<std::string, std::string> cases[] = {
      {"/dev/zero", "/dev/zero: holds a NUL byte: not a text file"},
      {(dir / "fifo.html").string(), (dir / "fifo.html").string() + ": is a FIFO, not a file"},
      {(dir / "folder").string(), (dir / "folder").string() + ": is a directory, not a file"},
      {(dir / "empty.html").string(), (dir / "empty.html").string() + ": the page is empty"},
  };
  for (const auto& [page, message] : cases) {
    std::string err;
    EXPECT_EQ(runWithin({"pool", "serve", "--listen", "127.0.0.1:0", "--page", page}, dir, err), 1) << page << ": " << err;
    EXPECT_EQ(err, "stsim pool: error: " + message + "\n") << page;
  }
}

// Arm values no workcell has (a base at 1e300, a stopping_time of 1e300 s) are refused, each
// naming its own key
TEST(HostileInput, ArmScenarioValuesNoWorkcellHasNameTheirKey) {
  const fs::path dir = freshDir("arm_values");
  const std::string motion = "waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}, {t: 0.1, q: [0, 0, 0, -1, 0, 1, 0]}]";
  const std::pair<std::string, std::string> cases[] = {
      {"arms:\n  - {name: a, model: panda, base: {xyz: [1e300, 0, 0]}, " + motion + "}\n",
       ":2: arms[0].base.xyz: [1e+300, 0, 0] is farther than 100 m from the workcell's origin"},
      {"arms:\n  - {name: a, model: panda, " + motion + "}\nsafety: {stopping_time: 1e300}\n",
       ":3: safety.stopping_time: 1e+300 s is more than the 60 s look-ahead limit"},
      {"arms:\n  - {name: a, model: panda, " + motion + "}\nsafety: {stopping_time: 1e300, horizon: 2}\n",
       ":3: safety.stopping_time: 1e+300 s is more than the 60 s look-ahead limit"},
  };
  int i = 0;  // 0.yaml, 1.yaml, ...
  for (const auto& [yaml, message] : cases) {
    const fs::path scen = dir / (std::to_string(i++) + ".yaml");
    std::ofstream(scen) << yaml;
    std::string err;
    EXPECT_EQ(runWithin({"arm", scen.string(), "--out", (dir / "out").string()}, dir, err), 1) << err;
    EXPECT_EQ(err, "stsim arm: error: " + scen.string() + message + "\n");
  }
}

// --set "" was accepted silently, and --set k=1.2,k=3 took one of the two without a word
TEST(HostileInput, SetWithNothingOrAKeyTwiceIsRefused) {
  const fs::path dir = freshDir("set_option");
  const std::vector<std::string> run{"highway", "--fcd", (kLanedrop / "lanedrop.fcd.xml").string(), "--net",
                                     (kLanedrop / "lanedrop.net.xml").string(), "--no-map", "--out", (dir / "out").string()};
  const std::pair<std::string, std::string> cases[] = {
      {"", "stsim highway: --set needs KEY=VALUE[,...], got nothing\n"},
      {"safe_time.vehicle_reaction=1.2,safe_time.vehicle_reaction=3",
       "stsim highway: --set safe_time.vehicle_reaction: safe_time.vehicle_reaction given twice\n"},
  };
  for (const auto& [value, message] : cases) {
    std::vector<std::string> args = run;
    args.insert(args.end(), {"--set", value});
    std::string err;
    EXPECT_EQ(runWithin(args, dir, err), 2) << value << ": " << err;
    EXPECT_EQ(err, message);
  }
  std::vector<std::string> args = run;
  args.insert(args.end(), {"--set", "safe_time.vehicle_reaction=1.2"});
  std::string err;
  EXPECT_EQ(runWithin(args, dir, err), 0) << err;
}

// A pool name that is not UTF-8 made summary.json invalid JSON and table.svg invalid XML; one with
// a terminal escape sequence was printed raw
TEST(HostileInput, APoolNameOfAnyBytesLeavesValidOutputs) {
  const fs::path dir = freshDir("pool_name");
  std::string text = slurp(kSource / "models/pool/scenarios/break.yaml");
  // the byte 0xE9 raw (YAML's "\xe9" is U+00E9, valid UTF-8); ESC and BEL as YAML escapes
  text.replace(text.find("name: break"), 11, std::string("name: \"caf") + '\xE9' + " \\e[31mred\\a\"");
  std::ofstream(dir / "s.yaml") << text;
  std::string err;
  ASSERT_EQ(runWithin({"pool", (dir / "s.yaml").string(), "--until", "0.2", "--out", (dir / "out").string()}, dir, err), 0) << err;
  for (const char* file : {"summary.json", "table.svg", "animation.html", "events.csv"})
    EXPECT_TRUE(st::io::validUtf8(slurp(dir / "out" / file))) << file;
  EXPECT_NE(slurp(dir / "out/summary.json").find("\"caf\xEF\xBF\xBD \\u001b[31mred\\u0007"), std::string::npos);
  EXPECT_NE(slurp(dir / "out/table.svg").find("<title>caf\xEF\xBF\xBD \xEF\xBF\xBD[31mred\xEF\xBF\xBD"), std::string::npos);
  const std::string out = slurp(dir / "stdout.txt");
  EXPECT_EQ(out.find('\x1b'), std::string::npos) << out;
  EXPECT_NE(out.find("caf\xEF\xBF\xBD \\x1b[31mred\\x07"), std::string::npos) << out;
}

// A pool run stopped at the event limit reported initial energy 0, momentum [0, 0] and shots: []
TEST(HostileInput, APoolRunStoppedAtTheEventLimitKeepsItsShot) {
  const fs::path dir = freshDir("pool_limit");
  std::string err;
  EXPECT_EQ(runWithin({"pool", (kSource / "models/pool/scenarios/break.yaml").string(), "--max-events", "5", "--out",
                       (dir / "out").string()}, dir, err), 1) << err;
  const std::string summary = slurp(dir / "out/summary.json");
  EXPECT_NE(summary.find("\"ending\": \"stopped\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"kinetic_energy_initial_J\": 5.4"), std::string::npos) << summary;  // 0.17 kg at 8 m/s
  EXPECT_EQ(summary.find("\"momentum_initial\": [0, 0]"), std::string::npos) << summary;
}

// pool --study fig13 --out D ignored --out (a minute of study, nothing written)
TEST(HostileInput, Fig13HonoursOut) {
  const fs::path dir = freshDir("fig13_out");
  std::ofstream(dir / "file") << "x";
  std::string err;
  EXPECT_EQ(runWithin({"pool", "--study", "fig13", "--out", (dir / "file/sub").string()}, dir, err), 1) << err;
  EXPECT_NE(err.find((dir / "file/sub").string() + ": cannot create the folder"), std::string::npos) << err;
}

// Disk full while drawing the conflict map: "no conflict map: ... No space left on device", exit 0.
// A full disk is a file-size limit here (write() fails with EFBIG past it, as ENOSPC on a full
// disk): room for the tables, none for the map.
TEST(HostileInput, AMapThatCannotBeWrittenFailsTheRun) {
  if (std::system("/usr/bin/python3 -c 'import matplotlib' 2>/dev/null") != 0) GTEST_SKIP() << "no python3-matplotlib";
  const fs::path dir = freshDir("map_full");
  std::string err;
  EXPECT_EQ(runWithin({"--bash-c", "ulimit -f 40; trap '' XFSZ; exec \"$@\"", "highway", "--fcd",
                       (kLanedrop / "lanedrop.fcd.xml").string(), "--net", (kLanedrop / "lanedrop.net.xml").string(),
                       "--out", (dir / "out").string()},
                      dir, err, 60),
            1)
      << err;
  EXPECT_NE(err.find((dir / "out/conflict_map.png").string() + ": conflict map failed"), std::string::npos) << err;
  // the tables were written whole
  EXPECT_NE(slurp(dir / "out/summary.json").find("\"ticks\""), std::string::npos);
}

}  // namespace

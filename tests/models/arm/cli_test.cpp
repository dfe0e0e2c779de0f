// `stsim arm` end to end: outputs, and bad input giving one line naming the trace line or the
// YAML key, a non-zero exit, and the warnings so far on disk.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include <starm/scenario.hpp>
#include <starm/settings.hpp>

#include "files.hpp"

namespace st::arm {
namespace {

namespace fs = std::filesystem;

struct Result {
  int code;
  std::string out, err;
};

using st::test::slurp;

Result stsim(const std::string& args, const fs::path& dir) {
  const std::string cmd = std::string(STSIM_BINARY) + " arm " + args + " > " + (dir / "stdout").string() + " 2> " +
                          (dir / "stderr").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "stdout"), slurp(dir / "stderr")};
}

fs::path tempDir(const std::string& name) { return st::test::freshDir("arm_cli", name); }

std::string scenario(const std::string& name) {
  return std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/" + name + ".yaml";
}

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(ArmCli, TwoPandasWritesWarningsAndSummary) {
  const fs::path d = tempDir("ok");
  const Result r = stsim(scenario("two_pandas") + " --out " + (d / "out").string(), d);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string summary = slurp(d / "out" / "summary.json");
  EXPECT_NE(summary.find("\"cycles\": 3001"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"stops\": 2"), std::string::npos) << summary;
  for (const char* key : {"\"p50\"", "\"p99\"", "\"max\"", "\"subdivisions\"", "\"reunions\"", "\"candidate_pairs\""})
    EXPECT_NE(summary.find(key), std::string::npos) << key;
  const std::string csv = slurp(d / "out" / "warnings.csv");
  EXPECT_EQ(csv.rfind("t_s,arm,link,capsule,other,distance_m,ttc_s,reason,stop\n", 0), 0u);
  EXPECT_NE(csv.find(",left,flange,"), std::string::npos);
  EXPECT_NE(csv.find(",right/"), std::string::npos);
  EXPECT_NE(csv.find("STOP"), std::string::npos);
  fs::remove_all(d);
}

TEST(ArmCli, CyclesOverTheBudgetAreCountedListedAndFlagged) {
  // a budget no cycle can keep (1 ns): every cycle is a miss, each listed with its time
  const fs::path d = tempDir("deadline");
  Result r = stsim(scenario("two_pandas") + " --budget-us 0.001 --out " + (d / "out").string(), d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("DEADLINE MISSED: 3001 of 3001 cycles over the 0.001 us budget"), std::string::npos) << r.out;
  const std::string summary = slurp(d / "out" / "summary.json");
  EXPECT_NE(summary.find("\"deadline\": {\"budget_us\": 0.001, \"missed\": 3001, \"cycles\": 3001, \"first_miss_s\": 0,"),
            std::string::npos) << summary;
  EXPECT_EQ(lines(slurp(d / "out" / "deadlines.csv")), 3002);
  // the default budget is the cycle time (1 ms): the summary says which
  r = stsim(scenario("two_pandas") + " --out " + (d / "out2").string(), d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(d / "out2" / "summary.json").find("\"deadline\": {\"budget_us\": 1000,"), std::string::npos);
  r = stsim(scenario("two_pandas") + " --budget-us 0 --out " + (d / "out3").string(), d);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--budget-us"), std::string::npos) << r.err;
  fs::remove_all(d);
}

TEST(ArmCli, PersonsWriteSeparationTermsPerCycle) {
  const fs::path d = tempDir("persons");
  const Result r = stsim(scenario("person_walkup") + " --out " + (d / "out").string(), d);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("persons (scaling): 0 STOP cycles"), std::string::npos) << r.out;
  const std::string csv = slurp(d / "out" / "ssm.csv");
  EXPECT_EQ(csv.rfind("t_s,arm,link,person,part,region,separation_m,S_p_m,S_h_m,S_r_m,S_s_m,C_m,Z_d_m,Z_r_m,dominant,", 0), 0u);
  EXPECT_EQ(lines(csv), 10002);  // one row per cycle for the one arm
  EXPECT_NE(csv.find(",visitor,r_hand,hand_fingers,"), std::string::npos);
  EXPECT_NE(csv.find(",SCALE\n"), std::string::npos);
  EXPECT_NE(slurp(d / "out" / "summary.json").find("\"ssm\": {\"response\": \"scaling\""), std::string::npos);
  fs::remove_all(d);
}

// A CSV trace of the two-Panda motion up to 1.2 s (past the first warnings), then `bad`.
// Returns the scenario; `badLine` the line number of `bad`, `cycles` the times before it.
fs::path badTrace(const fs::path& d, const std::string& bad, int& badLine, int& cycles) {
  const Scenario s = loadScenario(scenario("two_pandas"));
  auto src = makeSensor(s);
  std::ofstream csv(d / "trace.csv");
  csv << "t,arm,q1,q2,q3,q4,q5,q6,q7,qd1,qd2,qd3,qd4,qd5,qd6,qd7\n";
  csv.precision(17);
  Reading r;
  badLine = 2;
  cycles = 0;
  double last = -1.0;
  while (src->next(r) && r.t <= 1.2) {
    ++badLine;
    if (r.t != last) ++cycles, last = r.t;
    csv << r.t << ',' << s.arms[r.arm].name;
    for (double v : r.q) csv << ',' << v;
    for (double v : r.qdot) csv << ',' << v;
    csv << '\n';
  }
  csv << bad << '\n';
  csv.close();
  std::ofstream y(d / "scenario.yaml");
  y << "safety: {cycle_time: 0.001, reaction_time: 0.010, stopping_time: 0.200, min_separation: 0.02, horizon: 0.3}\n"
       "arms:\n"
       "  - {name: left, model: panda}\n"
       "  - {name: right, model: panda, base: {xyz: [1.1, 0.05, 0], rpy: [0, 0, 3.141592653589793]}}\n"
       "trace: trace.csv\n";
  return d / "scenario.yaml";
}

void expectBadInput(const std::string& name, const std::string& bad, const std::string& mention) {
  const fs::path d = tempDir(name);
  int badLine = 0, cycles = 0;
  const fs::path y = badTrace(d, bad, badLine, cycles);
  ASSERT_GT(cycles, 1100);
  const Result r = stsim(y.string() + " --out " + (d / "out").string(), d);
  EXPECT_EQ(r.code, 1) << name;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("stsim arm: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("trace.csv:" + std::to_string(badLine) + ":"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(mention), std::string::npos) << r.err;
  // results so far are on disk
  const std::string csv = slurp(d / "out" / "warnings.csv");
  EXPECT_NE(csv.find("STOP"), std::string::npos) << "warnings before the bad line were not flushed";
  const std::string summary = slurp(d / "out" / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"error\""), std::string::npos) << summary;
  // every complete cycle before the bad line ran
  EXPECT_NE(summary.find("\"cycles\": " + std::to_string(cycles) + ","), std::string::npos) << summary;
  fs::remove_all(d);
}

TEST(ArmCli, WrongJointCountNamesTheTraceLine) {
  expectBadInput("count", "1.201,left,0,-0.7,0,-2.3,0,1.5,0.7,0,0,0,0,0,0", "expected 7 angles and 7 rates");
}

TEST(ArmCli, NanAngleNamesTheTraceLine) {
  expectBadInput("nan", "1.201,left,0,nan,0,-2.3,0,1.5,0.7,0,0,0,0,0,0,0", "joint 2 angle is not a finite number");
}

TEST(ArmCli, AngleBeyondLimitNamesTheTraceLine) {
  expectBadInput("limit", "1.201,right,0,-0.7,0,0.5,0,1.5,0.7,0,0,0,0,0,0,0", "joint 4 angle 0.5 rad is beyond its limits");
}

TEST(ArmCli, ImplausibleJointRateNamesTheTraceLine) {
  // finite but absurd (a corrupt reading): used to turn every time to collision into zero
  expectBadInput("rate", "1.201,left,0,0,0,-1,0,1,0,0,0,0,0,0,0,1e300", "joint 7 rate 1e+300 rad/s is beyond its limit");
}

// A NUL byte in a trace line, and a line over 64 KiB (a device of NULs without a newline, such as
// /dev/zero, as `trace:` or to `arm stream`), are refused naming the trace line, at once
TEST(ArmCli, ANulByteOrAnEndlessLineInATraceNamesTheTraceLine) {
  expectBadInput("nul", std::string("1.201,left,0,-0.7") + '\0' + ",0,-2.3,0,1.5,0.7,0,0,0,0,0,0,0",
                 "a NUL byte: not a sensor trace");
  expectBadInput("long", "1.201,left," + std::string(70000, '0'), "a line longer than 64 KiB: not a sensor trace");
  const fs::path d = tempDir("devzero");
  std::ofstream(d / "s.yaml") << "arms:\n  - {name: left, model: panda}\ntrace: /dev/zero\n";
  const std::string cmd = "timeout 20 " + std::string(STSIM_BINARY) + " arm " + (d / "s.yaml").string() + " --out " +
                          (d / "o").string() + " > /dev/null 2> " + (d / "stderr").string();
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  EXPECT_EQ(slurp(d / "stderr"), "stsim arm: error: /dev/zero:1: a NUL byte: not a sensor trace (CSV text)\n");
  fs::remove_all(d);
}

TEST(ArmCli, UnknownArmModelNamesTheYamlKey) {
  const fs::path d = tempDir("model");
  std::ofstream(d / "s.yaml") << "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}]}\n"
                                 "  - {name: b, model: ur5, waypoints: [{t: 0, q: [0, 0, 0, 0, 0, 0]}]}\n";
  const Result r = stsim((d / "s.yaml").string() + " --out " + (d / "out").string(), d);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("s.yaml:3: arms[1].model: unknown arm model 'ur5'"), std::string::npos) << r.err;
  fs::remove_all(d);
}

TEST(ArmCli, WaypointBeyondLimitNamesTheYamlKey) {
  const fs::path d = tempDir("waypoint");
  std::ofstream(d / "s.yaml") << "arms:\n  - name: a\n    model: panda\n    waypoints:\n"
                                 "      - {t: 0, q: [0, 0, 0, -1, 0, 1, 0]}\n"
                                 "      - {t: 1, q: [0, 2.5, 0, -1, 0, 1, 0]}\n";
  const Result r = stsim((d / "s.yaml").string() + " --out " + (d / "out").string(), d);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("arms[0].waypoints[1].q: joint 2 angle 2.5 rad is beyond its limits"), std::string::npos) << r.err;
  fs::remove_all(d);
}

TEST(ArmCli, MissingScenarioIsAUsageErrorOrError) {
  const fs::path d = tempDir("usage");
  EXPECT_EQ(stsim("", d).code, 2);
  EXPECT_EQ(stsim("--frobnicate x.yaml", d).code, 2);
  EXPECT_EQ(stsim((d / "nope.yaml").string(), d).code, 1);
  fs::remove_all(d);
}


TEST(ArmCli, ConflictingReadingsNameBothTraceLines) {
  const fs::path d = tempDir("conflict");
  int badLine = 0, cycles = 0;
  const fs::path y = badTrace(d, "# the last time again", badLine, cycles);
  // the last reading (right at the last time) again, once as it is (read once) and once with
  // its last rate changed: the arm's state at that time is unknown
  std::string trace = slurp(d / "trace.csv");
  const std::size_t end = trace.rfind('\n', trace.rfind("# the last") - 1);
  const std::size_t begin = trace.rfind('\n', end - 1) + 1;
  const std::string last = trace.substr(begin, end - begin);
  std::string other = last.substr(0, last.rfind(',') + 1) + (last.substr(last.rfind(',') + 1) == "0" ? "0.01" : "0");
  std::ofstream(d / "trace.csv", std::ios::app) << last << "\n" << other << "\n";
  const Result r = stsim(y.string() + " --out " + (d / "out").string(), d);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("trace.csv:" + std::to_string(badLine + 2) + ": arm 'right' at t = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("differs from its reading at line " + std::to_string(badLine - 1)), std::string::npos) << r.err;
  // every cycle ran, the last with the first of the two readings (a bad next reading lets its
  // cycle finish, then stops the run)
  const std::string summary = slurp(d / "out" / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"error\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"cycles\": " + std::to_string(cycles) + ","), std::string::npos) << summary;
  fs::remove_all(d);
}

// Runs `stsim arm` on a long scenario, signals it once it writes warnings, returns its exit code.
int signalLongRun(int sig, const fs::path& d) {
  std::string yaml = slurp(scenario("two_pandas"));
  yaml.replace(yaml.find("duration: 3.0"), 13, "duration: 2000");
  std::ofstream(d / "long.yaml") << yaml;
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string out = (d / "out").string(), err = (d / "stderr").string(), y = (d / "long.yaml").string();
    std::freopen(err.c_str(), "w", stderr);
    std::freopen((d / "stdout").c_str(), "w", stdout);
    ::execl(STSIM_BINARY, STSIM_BINARY, "arm", y.c_str(), "--out", out.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // the handler is in place once the run writes warnings (they come after 1 s of simulated time)
  for (int i = 0; i < 3000 && lines(slurp(d / "out" / "warnings.csv")) < 2; ++i) ::usleep(10000);
  EXPECT_GE(lines(slurp(d / "out" / "warnings.csv")), 2) << "no warnings within 30 s";
  ::kill(pid, sig);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

// Each output on a full disk: one line naming the file, exit 1
TEST(ArmCli, AFullDiskIsAnErrorNamingTheFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path d = tempDir("full");
  // each output on a full device in turn (a symlink to /dev/full: no root, no tmpfs)
  for (const char* f : {"warnings.csv", "summary.json"}) {
    const fs::path out = d / (std::string("out_") + f);
    fs::create_directories(out);
    fs::create_symlink("/dev/full", out / f);
    const Result r = stsim(scenario("two_pandas") + " --out " + out.string(), d);
    EXPECT_EQ(r.code, 1) << f << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("write failed: " + (out / f).string()), std::string::npos) << r.err;
  }
  const Result r = stsim(scenario("two_pandas") + " --out " + (d / "out").string() + " --record-trace /dev/full", d);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("stsim arm: error: write failed: /dev/full"), std::string::npos) << r.err;
  fs::remove_all(d);
}

TEST(ArmCli, ADiskFillingMidRunIsAnErrorWithTheSummarySaying) {
  // a file size limit of a few KB (the write fails with EFBIG once warnings.csv, 8.5 KB, reaches it)
  const fs::path d = tempDir("fills");
  const Result r = stsim(scenario("two_pandas") + " --out " + (d / "out").string(), d);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_GT(fs::file_size(d / "out" / "warnings.csv"), 6000u);
  const std::string cmd = "ulimit -f 8; trap '' XFSZ; " + std::string(STSIM_BINARY) + " arm " + scenario("two_pandas") +
                          " --out " + (d / "lim").string() + " 2> " + (d / "stderr").string() + " > /dev/null";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
  const std::string err = slurp(d / "stderr");
  EXPECT_EQ(lines(err), 1) << err;
  EXPECT_NE(err.find("write failed: " + (d / "lim" / "warnings.csv").string()), std::string::npos) << err;
  const std::string summary = slurp(d / "lim" / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"error\""), std::string::npos) << summary;
  // what was written is whole rows (the stream's buffer went out in pieces: a row was cut)
  const std::string csv = slurp(d / "lim" / "warnings.csv");
  ASSERT_FALSE(csv.empty());
  EXPECT_EQ(csv.back(), '\n') << "a cut row at the end";
  std::istringstream rows(csv);
  for (std::string row; std::getline(rows, row);) EXPECT_EQ(std::count(row.begin(), row.end(), ','), 8) << row;
  fs::remove_all(d);
}

TEST(ArmCli, OutOfRangeServiceOptionsAreRefusedNamingTheOption) {
  const fs::path d = tempDir("opts");
  std::ofstream(d / "t.csv") << "t,arm,q...,qdot...\n";
  // bounded: were one taken, `timeout` ends the service it started
  const std::pair<std::string, std::string> cases[] = {
      {"serve " + scenario("two_pandas") + " --max-connections 0", "--max-connections: expected 1..100000, got 0"},
      {"serve " + scenario("two_pandas") + " --max-connections -1", "--max-connections: expected 1..100000, got -1"},
      {"serve " + scenario("two_pandas") + " --frame-timeout 0", "--frame-timeout: expected 1..3600000, got 0"},
      {"serve " + scenario("two_pandas") + " --frame-timeout -5", "--frame-timeout: expected 1..3600000, got -5"},
      {"serve " + scenario("two_pandas") + " --max-pending 0", "--max-pending: expected 1..100000, got 0"},
      {"serve " + scenario("two_pandas") + " --hello-timeout 0", "--hello-timeout: expected 1..3600000, got 0"},
      {"stream --connect 127.0.0.1:1 " + (d / "t.csv").string() + " --rate 1e-20",
       "--rate: expected 0 (as fast as possible) or a speed in 0.001..1e6, got 1e-20"},
      {"stream --connect 127.0.0.1:1 " + (d / "t.csv").string() + " --delay -1", "--delay: must not be negative, got -1"},
  };
  for (const auto& [args, why] : cases) {
    const std::string cmd = "timeout 5 " + std::string(STSIM_BINARY) + " arm " + args + " --out " + (d / "o").string() +
                            " > /dev/null 2> " + (d / "stderr").string();
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2) << args;
    const std::string err = slurp(d / "stderr");
    EXPECT_EQ(lines(err), 1) << err;
    EXPECT_NE(err.find(why), std::string::npos) << args << ": " << err;
  }
  fs::remove_all(d);
}

// Ctrl-C (and SIGTERM, SIGHUP) stop at a whole cycle: whole rows, a summary, 128 + signal
TEST(ArmCli, SignalsStopAtAWholeCycleWithASummary) {
  for (const auto& [sig, code] : {std::pair{SIGINT, 130}, std::pair{SIGTERM, 143}, std::pair{SIGHUP, 129}}) {
    const fs::path d = tempDir("signal" + std::to_string(sig));
    EXPECT_EQ(signalLongRun(sig, d), code);
    const std::string err = slurp(d / "stderr");
    EXPECT_NE(err.find("interrupted at t = "), std::string::npos) << err;
    EXPECT_NE(err.find("results so far written"), std::string::npos) << err;
    const std::string summary = slurp(d / "out" / "summary.json");
    EXPECT_NE(summary.find("\"status\": \"interrupted\""), std::string::npos) << summary;
    EXPECT_NE(summary.find("\"stopped_at_s\": "), std::string::npos) << summary;
    EXPECT_EQ(summary.find("\"cycles\": 2000001"), std::string::npos) << "ran to the end: " << summary;
    // every row whole: nine fields and a newline
    const std::string csv = slurp(d / "out" / "warnings.csv");
    ASSERT_FALSE(csv.empty());
    EXPECT_EQ(csv.back(), '\n');
    std::istringstream in(csv);
    for (std::string row; std::getline(in, row);) EXPECT_EQ(std::count(row.begin(), row.end(), ','), 8) << row;
    fs::remove_all(d);
  }
}

// stsim arm --settings prints the table; --set refuses what the YAML refuses, in its words, naming
// the option; a value it accepts is the value in effect.
TEST(ArmCli, SettingsPrintsTheTableAndSetSpeaksTheYamlsWords) {
  const fs::path d = tempDir("settings");
  Result r = stsim("--settings", d);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, settingsReferenceMarkdown());
  for (const Setting& s : armSettings()) {
    // beyond its range, or a word it does not take
    const std::string bad = s.type == SettingType::Number || s.type == SettingType::Integer ? "1e9" : "nonsense";
    Scenario scratch;
    std::string problem;
    try {
      applySettingText(scratch, s, bad);
    } catch (const SettingError& e) {
      problem = e.problem();
    }
    ASSERT_FALSE(problem.empty()) << s.key;
    r = stsim(scenario("two_pandas") + " --out " + (d / "o").string() + " --set " + s.key + "=" + bad, d);
    EXPECT_EQ(r.code, 2) << s.key;
    EXPECT_EQ(r.err, "stsim arm: --set " + std::string(s.key) + ": " + problem + "\n");
  }
  // the values in effect: the scenario's, the command line's over them (two_pandas gives no braking:
  // braking.stopping_time follows the command line's safety.stopping_time)
  r = stsim("--settings " + scenario("two_pandas") + " --set safety.stopping_time=0.25,ssm.response=pfl", d);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("| `safety.stopping_time` | number in [0, 60] s | 0.25 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| `braking.stopping_time` | number in [0, 60] s | 0.25 |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| `ssm.response` | one of stop, scaling, pfl | pfl |"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("| in effect |"), std::string::npos) << r.out;
  // --response is ssm.response: its words, its option
  r = stsim(scenario("person_walkup") + " --out " + (d / "o").string() + " --response maybe", d);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "stsim arm: --response: must be one of stop, scaling, pfl, got 'maybe'\n");
  // the service reads its scenario alike
  r = stsim("serve " + scenario("two_pandas") + " --out " + (d / "o").string() + " --set safety.cycle_time=99", d);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "stsim arm: --set safety.cycle_time: 99 s is more than the 60 s look-ahead limit\n");
  // an unknown key, a key twice
  r = stsim(scenario("two_pandas") + " --set safety.cycle=1", d);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown setting 'safety.cycle'"), std::string::npos) << r.err;
  r = stsim(scenario("two_pandas") + " --set safety.horizon=1,safety.horizon=2", d);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("safety.horizon given twice"), std::string::npos) << r.err;
  fs::remove_all(d);
}

}  // namespace
}  // namespace st::arm

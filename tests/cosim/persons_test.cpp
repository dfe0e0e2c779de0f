// Persons on foot are foes, read live each step. Checked against SUMO itself: the backend's
// persons are those of SUMO's own FCD trace of the same run (riders excluded), and every contact
// SUMO reports between a vehicle and a person was warned ahead by the box detector; the
// pedestrian conflicts and the summary's count agree with conflicts.csv.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>
#include <set>
#include <vector>

#include "test_util.hpp"
#include <stcore/cpu_clock.hpp>
#include <stcosim/backend.hpp>
#include <stcosim/scenario.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;

// the persons in SUMO's FCD output, by time (rounded to ms) and id: x, y, angle, speed
struct FcdPerson {
  double x, y, angle, speed;
};
std::map<long, std::map<std::string, FcdPerson>> fcdPersons(const std::filesystem::path& fcd) {
  std::map<long, std::map<std::string, FcdPerson>> out;
  const std::regex step("<timestep time=\"([0-9.]+)\""), vehicleOpen("<vehicle [^>]*[^/]>"), vehicleClose("</vehicle>");
  const std::regex person("<person id=\"([^\"]+)\" x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" angle=\"([-0-9.]+)\"[^>]* speed=\"([-0-9.]+)\"");
  long t = -1;
  bool inVehicle = false;
  for (const std::string& line : lines(slurp(fcd))) {
    std::smatch m;
    if (std::regex_search(line, m, step)) t = std::lround(std::stod(m[1]) * 1000.0);
    if (std::regex_search(line, vehicleOpen)) inVehicle = true;
    if (std::regex_search(line, vehicleClose)) inVehicle = false;
    if (!inVehicle && std::regex_search(line, m, person))
      out[t][m[1]] = {std::stod(m[2]), std::stod(m[3]), std::stod(m[4]), std::stod(m[5])};
  }
  return out;
}

TEST(Persons, BackendReadsTheWalkersOfSumosOwnTrace) {
  const auto dir = freshDir("persons_fcd");
  Scenario s = loadScenario(sourceDir() / "networks/crosswalk/scenario.yaml");
  s.end = 200.0;
  const auto fcd = dir / "trace.fcd.xml";
  std::vector<std::string> args = sumoArguments(s);
  args.insert(args.end(), {"--fcd-output", fcd.string(), "--fcd-output.attributes", "x,y,angle,speed"});
  auto b = startLibsumo(SumoLaunch{args, false, "", ""});
  // SUMO labels an output with its step's begin time: what the backend reads after the step that
  // ends at t is the trace's row of t - step length
  std::map<long, std::vector<SumoVehicle>> read;
  const Backend::ReadCost before = b->readCost();
  const double c0 = threadCpuSeconds();
  while (b->running()) {
    b->step();
    read[std::lround((b->time() - b->deltaT()) * 1000.0)] = b->persons();
  }
  const double loop = threadCpuSeconds() - c0;
  // the reads' cost by part (bench/cosim_overhead --junction): each read here, within the loop's CPU
  const Backend::ReadCost cost = b->readCost();
  EXPECT_GT(cost.vehicles, before.vehicles);
  EXPECT_GT(cost.lights, before.lights);
  EXPECT_GT(cost.persons, before.persons);
  EXPECT_LT(cost.vehicles + cost.lights + cost.persons - before.vehicles - before.lights - before.persons, loop);
  b->close();
  const auto truth = fcdPersons(fcd);
  std::size_t compared = 0;
  std::set<std::uint32_t> serials;
  for (const auto& [t, persons] : read) {
    const auto it = truth.find(t);
    const std::size_t expected = it == truth.end() ? 0 : it->second.size();
    ASSERT_EQ(persons.size(), expected) << "t = " << static_cast<double>(t) * 1e-3;
    for (const SumoVehicle& p : persons) {
      const FcdPerson& f = it->second.at(p.id);
      EXPECT_NEAR(p.x, f.x, 0.006) << p.id;  // FCD writes 2 decimals
      EXPECT_NEAR(p.y, f.y, 0.006) << p.id;
      EXPECT_NEAR(p.angle, f.angle, 0.006) << p.id;
      EXPECT_NEAR(p.speed, f.speed, 0.006) << p.id;
      serials.insert(p.serial);
      ++compared;
    }
  }
  EXPECT_GT(compared, 5000u);
  EXPECT_GT(serials.size(), 40u);  // 49 persons walk in the first 200 s
}

TEST(Persons, EveryContactWithAPersonWarnedAheadAndCountedApart) {
  const auto dir = freshDir("persons_run");
  const auto src = sourceDir() / "networks/crosswalk";
  const auto run = runStsim({"highway", (src / "scenario.yaml").string(), "--no-map", "--out", (dir / "out").string()}, dir);
  ASSERT_EQ(run.code, 0) << run.err;
  // SUMO's contacts with a person (the persons are the flows "p<from><to>")
  const auto rows = lines(slurp(dir / "out/collision_warnings.csv"));
  ASSERT_FALSE(rows.empty());
  const auto header = splitCsv(rows[0]);
  auto col = [](const std::vector<std::string>& h, const char* name) {
    const auto it = std::find(h.begin(), h.end(), name);
    EXPECT_NE(it, h.end()) << name;
    return static_cast<std::size_t>(it - h.begin());
  };
  const std::size_t victim = col(header, "victim"), warned = col(header, "collider_warned"), lead = col(header, "lead_time_s");
  int withPersons = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const auto f = splitCsv(rows[i]);
    if (f[victim].rfind('p', 0) != 0) continue;
    ++withPersons;
    EXPECT_EQ(f[warned], "1") << rows[i];
    EXPECT_GT(std::stod(f[lead]), 0.0) << rows[i];
  }
  EXPECT_GE(withPersons, 2);
  // conflicts.csv's pedestrian rows: a vehicle and a person, the summary's count
  const auto conflicts = lines(slurp(dir / "out/conflicts.csv"));
  ASSERT_FALSE(conflicts.empty());
  const auto ch = splitCsv(conflicts[0]);
  const std::size_t type = col(ch, "type"), first = col(ch, "first"), second = col(ch, "second");
  int pedestrian = 0;
  for (std::size_t i = 1; i < conflicts.size(); ++i) {
    const auto f = splitCsv(conflicts[i]);
    const bool person = f[first].rfind('p', 0) == 0 || f[second].rfind('p', 0) == 0;
    EXPECT_EQ(f[type] == "pedestrian", person) << conflicts[i];
    pedestrian += f[type] == "pedestrian";
  }
  EXPECT_GT(pedestrian, 0);
  const std::string summary = slurp(dir / "out/summary.json");
  EXPECT_NE(summary.find("\"pedestrian\": " + std::to_string(pedestrian)), std::string::npos) << summary;
}

}  // namespace
}  // namespace st::cosim
